-- 13_obj_mtl.lua: an OBJ model with its .mtl materials: a crate whose sides
-- take a texture map and whose caps are polished steel, placed three times.
--   build/bin/lancer examples/13_obj_mtl.lua [out.png]
--
-- load_obj reads the model's usemtl and mtllib lines; each material of
-- crate.mtl becomes a lancer material (Kd, Ks, Ns, illum, map_Kd: the
-- manual's table), and faces keep their own. One material is replaced by
-- name for the third crate.
local lancer = require "lancer"
local here = (arg and arg[0] or ""):match("^(.*)/[^/]*$") or "."

local scene = lancer.scene{
  camera = lancer.camera{from = {2.2, 2.2, -3.6}, at = {0, 0.5, 0.3}, fov = 50},
  background = {0.3, 0.35, 0.45},
  ambient = 0.2,
  max_depth = 2,
}
scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                       material = lancer.material{color = {0.5, 0.55, 0.5}}})

local crate = lancer.load_obj(here .. "/assets/crate.obj")
local red_caps = lancer.load_obj(here .. "/assets/crate.obj", {materials = {
  steel = lancer.material{color = {0.8, 0.1, 0.05}, ks = 0.5, alpha = 40,
                          absorb = "diffuse"}}})
scene:add(crate:moved(lancer.rotate({0, 1, 0}, 20)),
          crate:moved(lancer.translate(1.3, 0, 0.6)),
          red_caps:moved(lancer.translate(-1.2, 0, 0.9)))

scene:add(lancer.point_light{position = {-2, 5, -3}, intensity = 30})

local img = scene:render{width = 320, height = 200, samples = 4}
img:save(arg and arg[1] or "13_obj_mtl.png")
print(table.concat(crate.material_names, ", "), #crate.warnings)
