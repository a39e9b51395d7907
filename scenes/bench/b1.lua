-- b1.lua: docs/bench-scenes.md's B1 "mirror room": a closed room, three spheres, a cube,
-- two point lights and mirror walls, 3 bounces.
-- Usage: lancer scenes/bench/b1.lua [samples] [out.png]   (samples 1 or 16)
-- Prints one line to stderr: bench b1 lua=<s> build=<s> trace=<s> rays=<n> ...
local lancer = require "lancer"
local samples = tonumber(arg and arg[1]) or 1
local out = arg and arg[2]
local t0 = os.clock()   -- CPU time: building is single-threaded, so it is wall time too

-- absorb = 'diffuse': the colour scales ambient and diffuse only (POV-Ray's
-- model, docs/bench-scenes.md's shading); Phong and mirror terms are not tinted.
local function mat(c, ka, kd, ks, n, kr)
  return lancer.material{color = c, ka = ka, kd = kd, ks = ks, alpha = n, kr = kr,
                         absorb = "diffuse"}
end
local M = {
  floor   = mat({0.75, 0.72, 0.65}, 0.1, 0.7, 0, 1, 0.3),
  ceiling = mat({0.90, 0.90, 0.90}, 0.1, 0.7, 0, 1, 0.3),
  left    = mat({0.80, 0.30, 0.30}, 0.1, 0.7, 0, 1, 0.3),
  right   = mat({0.30, 0.40, 0.80}, 0.1, 0.7, 0, 1, 0.3),
  back    = mat({0.80, 0.80, 0.80}, 0.1, 0.7, 0, 1, 0.3),
  front   = mat({0.60, 0.80, 0.60}, 0.1, 0.7, 0, 1, 0.3),
  mirror  = mat({1, 1, 1},          0,   0,   0, 1, 0.9),
  green   = mat({0.10, 0.80, 0.10}, 0.1, 0.9, 0, 1, 0),
  shiny   = mat({0.95, 0.95, 0.95}, 0.1, 0.6, 0.8, 50, 0),
  boxm    = mat({0.80, 0.55, 0.20}, 0.1, 0.8, 0, 1, 0),
}

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 2, 5.5}, at = {0, 1.2, -2}, fov = 70},
  background = 0, ambient = 1, max_depth = 3}

-- The room: interior x in [-4, 4], y in [0, 5], z in [-6, 6]; infinite
-- planes, each normal pointing into the room.
local function wall(point, normal, m)
  scene:add(lancer.plane{point = point, normal = normal, material = m})
end
wall({0, 0, 0},  {0, 1, 0},  M.floor)
wall({0, 5, 0},  {0, -1, 0}, M.ceiling)
wall({-4, 0, 0}, {1, 0, 0},  M.left)
wall({4, 0, 0},  {-1, 0, 0}, M.right)
wall({0, 0, -6}, {0, 0, 1},  M.back)
wall({0, 0, 6},  {0, 0, -1}, M.front)

scene:add(lancer.sphere{center = {-1.6, 1.2, -2.0}, radius = 1.2, material = M.mirror})
scene:add(lancer.sphere{center = {1.8, 0.8, -0.5},  radius = 0.8, material = M.green})
scene:add(lancer.sphere{center = {0.2, 0.7, 1.2},   radius = 0.7, material = M.shiny})
scene:add(lancer.box{min = {1.0, 0.0, -4.4}, max = {2.6, 1.6, -2.8}, material = M.boxm})

-- Point lights as POV-Ray's and Tachyon's: no distance falloff.
scene:add(lancer.point_light{position = {0, 4.5, 2.0}, color = {0.7, 0.7, 0.7},
                             falloff = "none"})
scene:add(lancer.point_light{position = {-3, 3, -4.5}, color = {0.6, 0.35, 0.08},
                             falloff = "none"})
local lua_seconds = os.clock() - t0

local img, stats = scene:render{width = 1280, height = 720, samples = samples}
if out then img:save(out, {encoding = "linear"}) end
local rays = 0
for _, n in pairs(stats.rays) do rays = rays + n end
io.stderr:write(("bench b1 " ..
  "lua=%.4f build=%.4f trace=%.4f rays=%d nodes=%d prims=%d\n"):format(
  lua_seconds, stats.compile_seconds, stats.trace_seconds, rays, stats.bvh_nodes,
  stats.primitives))
