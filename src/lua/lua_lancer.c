/* lua_lancer.c: the Lua binding's module, a thin layer over lancer.h: require
** "lancer.core" gathers what the lua_*.c files register. */
#include <limits.h>
#include <lauxlib.h>
#include <lua.h>
#include "lancer.h"
#include "lua_lancer.h"
#include "lua_binding.h"

void lb_class(lua_State *L, const char *name, const luaL_Reg *meta,
              const luaL_Reg *methods)
{
    luaL_newmetatable(L, name);
    luaL_setfuncs(L, meta, 0);
    if (methods) {
        lua_newtable(L);
        luaL_setfuncs(L, methods, 0);
        lua_setfield(L, -2, "methods");
    }
    lua_pop(L, 1);
}

/* ---- memory the collector cannot see ------------------------------------ */

/* An image's pixels, a mesh, a scene's BVH live in the core, behind an
** 8-byte userdata: Lua's collector sees none of it, and 40 discarded
** 2000x2000 renders piled up to 1.78 GB. So the binding tells it what
** the core grew by (lc_memory_used) since it last did. A step by that
** much hurries an incremental cycle and starts a minor collection, which
** frees the images that died young. Generational mode forgets that debt
** after each minor collection and starts a major one only when Lua's own
** heap has doubled, so an image that lived long enough to grow old would
** wait for that: once the core has grown by more than the Lua heap since
** the last full collection, the binding asks for one. Its cost is that of
** the Lua heap, paid at most once per as many bytes of core memory. */
typedef struct {
    size_t last;           /* lc_memory_used() when last charged */
    size_t pending;        /* growth charged since the last full collection */
} gc_account;

static const char account_key = 'a';      /* registry[&account_key]: a gc_account */

void lb_check_file(lua_State *L, int arg, const char *path, int writing)
{
    if (lua_getfield(L, LUA_REGISTRYINDEX, LB_FILE_GATE) != LUA_TFUNCTION) {
        lua_pop(L, 1);
        return;
    }
    lua_pushstring(L, path);
    lua_pushboolean(L, writing);
    lua_call(L, 2, 2);
    if (!lua_toboolean(L, -2)) {
        const char *why = lua_tostring(L, -1);
        luaL_argerror(L, arg, why ? why : "the host refused the file");
    }
    lua_pop(L, 2);
}

void lb_charge(lua_State *L)
{
    lua_rawgetp(L, LUA_REGISTRYINDEX, &account_key);
    gc_account *a = lua_touserdata(L, -1);
    lua_pop(L, 1);                      /* the registry keeps it */
    if (!a)
        return;
    size_t used = lc_memory_used();
    size_t grown = used > a->last ? used - a->last : 0;
    a->last = used;
    if (!grown || !lua_gc(L, LUA_GCISRUNNING))  /* stopped: the script's choice */
        return;
    a->pending += grown;
    size_t heap = (size_t)lua_gc(L, LUA_GCCOUNT) * 1024;
    if (a->pending > heap) {
        lua_gc(L, LUA_GCCOLLECT);
        a->pending = 0;
        a->last = lc_memory_used();
    } else if (grown >= 1024) {
        lua_gc(L, LUA_GCSTEP, grown / 1024 < INT_MAX ? (int)(grown / 1024) : INT_MAX);
    }
}

int luaopen_lancer_core(lua_State *L)
{
    gc_account *a = lua_newuserdatauv(L, sizeof *a, 0);
    a->last = lc_memory_used();
    a->pending = 0;
    lua_rawsetp(L, LUA_REGISTRYINDEX, &account_key);
    lua_newtable(L);
    lb_material_register(L);
    lb_light_register(L);
    lb_camera_register(L);
    lb_shapes_register(L);
    lb_mesh_register(L);
    lb_scene_register(L);
    lb_render_register(L);
    lb_explain_register(L);
    lb_image_register(L);
    lb_motion_register(L);
    lb_scene_objects_register(L);
    lb_query_register(L);
    lb_texture_register(L);
    lb_csg_register(L);
    lb_hook_register(L);
    lua_pushstring(L, LC_VERSION);
    lua_setfield(L, -2, "version");
    lua_pushstring(L, "lancer " LC_VERSION);
    lua_setfield(L, -2, "_VERSION");
    return 1;
}
