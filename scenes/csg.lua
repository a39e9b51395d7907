-- csg.lua: constructive solid geometry, the classic way: a box and a sphere
-- intersected with three cylinders drilled out, a torus ring cut open by a
-- box, a lathe-like stack of cones merged with a sphere, and a die (a cube
-- rounded by a sphere, dimpled by spheres) on a reflecting floor. The same
-- scene as tools/bench/scenes.lua's csg, which `make bench` writes for
-- POV-Ray 3.7 (docs/bench-scenes.md's conventions: no light falloff, POV-Ray's
-- colouring, 1280x720, 3 bounces).
-- Usage: lancer scenes/csg.lua [samples] [out.png]   (or: lancer scenes/csg.lua out.png)
-- Prints one line to stderr: bench csg lua=<s> build=<s> trace=<s> rays=<n> ...
local lancer = require "lancer"
local samples, out = 1, nil
if arg and tonumber(arg[1]) then
  samples, out = tonumber(arg[1]), arg[2]
elseif arg then
  out = arg[1]
end
local t0 = os.clock()

-- absorb = 'diffuse': the colour scales ambient and diffuse only (POV-Ray's model).
local function mat(c, ka, kd, ks, n, kr)
  return lancer.material{color = c, ka = ka, kd = kd, ks = ks, alpha = n, kr = kr,
                         absorb = "diffuse"}
end
local M = {
  floor = mat({0.7, 0.7, 0.68}, 0.1, 0.7, 0, 1, 0.25),
  red   = mat({0.85, 0.2, 0.15}, 0.1, 0.8, 0.4, 40, 0),
  gold  = mat({0.9, 0.7, 0.25}, 0.1, 0.8, 0.6, 60, 0),
  blue  = mat({0.2, 0.4, 0.9}, 0.1, 0.8, 0, 1, 0),
  green = mat({0.25, 0.75, 0.35}, 0.1, 0.8, 0.3, 30, 0),
  white = mat({0.92, 0.92, 0.9}, 0.1, 0.8, 0.5, 50, 0.15),
}

local scene = lancer.scene{
  camera = lancer.camera{from = {0.6, 4.4, -8.5}, at = {0, 0.9, 0}, fov = 62},
  background = {0.45, 0.55, 0.7}, ambient = 1, max_depth = 3}
-- just under the solids standing on it: no face of theirs lies in it
scene:add(lancer.plane{point = {0, -0.01, 0}, normal = {0, 1, 0}, material = M.floor})

-- The classic: (box & sphere) - (x, y and z cylinders).
local function drill(c, a)
  return lancer.cylinder{base = {c[1] - a[1], c[2] - a[2], c[3] - a[3]},
                         top = {c[1] + a[1], c[2] + a[2], c[3] + a[3]}, radius = 0.52,
                         material = M.blue}
end
scene:add(lancer.difference{
  lancer.intersection{
    lancer.box{min = {-1, 0, -1}, max = {1, 2, 1}, material = M.red},
    lancer.sphere{center = {0, 1, 0}, radius = 1.32, material = M.gold}},
  drill({0, 1, 0}, {1.5, 0, 0}), drill({0, 1, 0}, {0, 1.5, 0}),
  drill({0, 1, 0}, {0, 0, 1.5})})

-- A torus ring with a quarter cut away.
scene:add(lancer.difference{
  lancer.torus{center = {-3.2, 0.45, 1.2}, axis = {0, 1, 0}, major = 1.05, minor = 0.45,
               material = M.green},
  lancer.box{min = {-3.3, -0.5, 1.3}, max = {-1.5, 1.5, 3}, material = M.gold}})

-- A lathe-like stack of cones and a knob, merged: one solid, no inner faces.
local function cone(y0, y1, r0, r1)
  return lancer.cone{base = {3.2, y0, 1.2}, top = {3.2, y1, 1.2}, base_radius = r0,
                     top_radius = r1, material = M.white}
end
scene:add(lancer.merge{
  cone(0, 0.25, 0.9, 0.8), cone(0.22, 1.3, 0.75, 0.3), cone(1.25, 1.6, 0.32, 0.55),
  cone(1.55, 2.3, 0.5, 0.15),
  lancer.sphere{center = {3.2, 2.45, 1.2}, radius = 0.28, material = M.white}})

-- A die: a cube rounded by a sphere, its pips dimples cut by spheres.
local function pip(c, r)
  return lancer.sphere{center = c, radius = r, material = M.red}
end
scene:add(lancer.difference{
  lancer.intersection{
    lancer.box{min = {-2.5, 0, -3.4}, max = {-1.1, 1.4, -2}, material = M.white},
    lancer.sphere{center = {-1.8, 0.7, -2.7}, radius = 0.95, material = M.white}},
  pip({-1.8, 0.7, -3.65}, 0.33), pip({-2.1, 1.65, -3.0}, 0.3),
  pip({-1.5, 1.65, -2.4}, 0.3), pip({-0.85, 0.4, -3.0}, 0.28),
  pip({-0.85, 1.0, -2.4}, 0.28)})

-- Point lights as POV-Ray's: no distance falloff.
scene:add(lancer.point_light{position = {-5, 9, -7}, color = {0.8, 0.8, 0.8},
                             falloff = "none"})
scene:add(lancer.point_light{position = {6, 5, -3}, color = {0.35, 0.3, 0.25},
                             falloff = "none"})
local lua_seconds = os.clock() - t0

local img, stats = scene:render{width = 1280, height = 720, samples = samples}
if out then img:save(out, {encoding = "linear"}) end
local rays = 0
for _, n in pairs(stats.rays) do rays = rays + n end
io.stderr:write(("bench csg " ..
  "lua=%.4f build=%.4f trace=%.4f rays=%d nodes=%d prims=%d csg_tests=%d\n"):format(
  lua_seconds, stats.compile_seconds, stats.trace_seconds, rays, stats.bvh_nodes,
  stats.primitives, stats.csg_tests))
