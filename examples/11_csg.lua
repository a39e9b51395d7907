-- 11_csg.lua: constructive solid geometry: solids combined by union,
-- intersection, difference and merge, cut faces coloured by the cutter or
-- by the object, one object placed twice.
--   build/bin/lancer examples/11_csg.lua out.png
local lancer = require "lancer"

local out = arg and arg[1] or "csg.png"

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 4.2, -8}, at = {0, 0.6, 0}, fov = 48},
  background = {0.05, 0.06, 0.1}, ambient = 0.08,
}
scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                       material = lancer.material{color = 0.6, kr = 0.15}})
scene:add(lancer.point_light{position = {-3, 7, -6}, intensity = 90})

local red = lancer.material{color = {0.85, 0.2, 0.15}, ks = 0.4, alpha = 40}
local blue = lancer.material{color = {0.2, 0.4, 0.9}}
local gold = lancer.material{color = {0.9, 0.7, 0.2}, ks = 0.5, alpha = 60}

-- The classic: a box and a sphere intersected, three cylinders drilled out.
local function rod(axis)
  local a = {axis[1] * 1.2, axis[2] * 1.2, axis[3] * 1.2}
  return lancer.cylinder{base = {-a[1], -a[2], -a[3]}, axis = {2 * a[1], 2 * a[2], 2 * a[3]},
                         radius = 0.32, material = blue}
end
local classic = lancer.difference{
  lancer.intersection{
    lancer.box{min = {-0.7, -0.7, -0.7}, max = {0.7, 0.7, 0.7}, material = red},
    lancer.sphere{center = {0, 0, 0}, radius = 0.92, material = gold}},
  rod{1, 0, 0}, rod{0, 1, 0}, rod{0, 0, 1}}
-- Placed twice: the same object, turned and moved.
scene:add(classic:moved(lancer.translate(-2.6, 0.7, 0.8) * lancer.rotate("y", 20)))
scene:add(classic:moved(lancer.translate(0, 0.7, 0) * lancer.rotate({1, 1, 0}, 35)))

-- cut = 'object': the faces the ball cuts take the block's own material.
local block = lancer.box{min = {-0.6, 0, -0.6}, max = {0.6, 1.2, 0.6}, material = gold}
scene:add(lancer.difference{block, lancer.sphere{center = {-0.6, 1.2, -0.6}, radius = 0.75,
                                                 material = blue}, cut = "object"}
          :moved(lancer.translate(2.6, 0, 0.8)))

-- merge: one solid, no inner faces; a torus ring cut by a box.
scene:add(lancer.merge{
  lancer.sphere{center = {-1.3, 0.45, -2}, radius = 0.45, material = red},
  lancer.sphere{center = {-0.8, 0.45, -2}, radius = 0.45, material = red}})
scene:add(lancer.difference{
  lancer.torus{center = {1.2, 0.3, -2}, axis = {0, 1, 0}, major = 0.65, minor = 0.3,
               material = blue},
  lancer.box{min = {1.2, -1, -3}, max = {2.5, 1, -2}, material = gold}})

for _, o in ipairs(scene:objects()) do print(o.kind) end
scene:render{width = 480, height = 320, samples = 4}:save(out)
