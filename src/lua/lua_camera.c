/* lua_camera.c: the Lua side of cameras, over their field table. */
#include <stddef.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_fields.h"
#include "lua_binding.h"

#define F(name, type, required, shown) \
    {#name, offsetof(lc_camera, name), type, required, shown, NULL, NULL, NULL, 0, 0}

/* In the order the constructor reads them and __tostring writes them; a
** pinhole camera's (aperture 0) without its lens. */
static const lb_field fields[] = {
    F(from, LB_VEC3, 1, LB_SHOWN), F(at, LB_VEC3, 1, LB_SHOWN),
    F(up, LB_VEC3, 0, LB_SHOWN),
    F(fov, LB_NUMBER, 0, LB_SHOWN), F(aperture, LB_NUMBER, 0, LB_SHOWN_CHANGED),
    F(focus, LB_NUMBER, 0, LB_SHOWN_WITH_PREV),
    {NULL, 0, LB_NUMBER, 0, LB_SHOWN, NULL, NULL, NULL, 0, 0}
};

static int w_camera(lua_State *L)
{
    lb_record_open(L, 1, fields);
    lc_camera c = lc_camera_default();
    lb_record_read(L, 1, &c, fields, 0);
    lc_error err;
    if (lc_camera_check(&c, &err))
        return lf_raise(L, 1, &err);
    lb_camera_push(L, &c);
    return 1;
}

static int w_camera_tostring(lua_State *L)
{
    const lc_camera *c = &((lb_ud_camera *)luaL_checkudata(L, 1, LB_CAMERA))->c;
    lc_camera def = lc_camera_default();
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    lb_record_tostring(&b, "lancer.camera", c, &def, fields);
    luaL_pushresult(&b);
    return 1;
}

static int w_camera_index(lua_State *L)
{
    const lc_camera *c = &((lb_ud_camera *)luaL_checkudata(L, 1, LB_CAMERA))->c;
    const lb_field *f = lb_record_field(fields, luaL_checkstring(L, 2));
    if (f)
        lb_record_push(L, c, f);
    else
        lua_pushnil(L);
    return 1;
}

void lb_camera_push(lua_State *L, const lc_camera *c)
{
    lb_ud_camera *u = lua_newuserdatauv(L, sizeof *u, 0);
    u->c = *c;
    luaL_setmetatable(L, LB_CAMERA);
}

void lb_camera_register(lua_State *L)
{
    static const luaL_Reg meta[] = {
        {"__tostring", w_camera_tostring}, {"__index", w_camera_index}, {NULL, NULL}};
    lb_class(L, LB_CAMERA, meta, NULL);
    lua_pushcfunction(L, w_camera);
    lua_setfield(L, -2, "camera");
}
