-- b2.lua: B2 "many spheres" of docs/bench-scenes.md: N spheres on a ground plane.
-- Usage: lancer scenes/bench/b2.lua N [out.png] [samples]
local lancer = require "lancer"
local N = tonumber(arg and arg[1]) or 1000
local out = arg and arg[2]
local t0 = os.clock()   -- CPU time: building is single-threaded, so it is wall time too

-- The benchmark's PRNG (a 64-bit LCG; Lua integers wrap mod 2^64).
local s = 1
local function u()
  s = s * 6364136223846793005 + 1442695040888963407
  return (s >> 11) * (1.0 / 9007199254740992.0)
end

local PALETTE = {{0.9, 0.2, 0.2}, {0.2, 0.9, 0.2}, {0.2, 0.3, 0.9}, {0.9, 0.9, 0.2},
                 {0.9, 0.2, 0.9}, {0.2, 0.9, 0.9}, {0.95, 0.95, 0.95}, {0.9, 0.5, 0.1}}
local mats = {}
for k, c in ipairs(PALETTE) do
  mats[k] = lancer.material{color = c, ka = 0.1, kd = 0.8, absorb = "diffuse"}
end

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 12, 62}, at = {0, 0, 0}, fov = 60},
  background = {0.5, 0.7, 1.0}, ambient = 1, max_depth = 3}
scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
  material = lancer.material{color = 0.6, ka = 0.1, kd = 0.8, absorb = "diffuse"}})
scene:add(lancer.point_light{position = {40, 60, 30}, falloff = "none"})
local sphere, add = lancer.sphere, scene.add
for k = 0, N - 1 do
  local x = -50 + 100 * u()
  local z = -50 + 100 * u()
  local r = 0.05 + 0.25 * u()
  add(scene, sphere{center = {x, r, z}, radius = r, material = mats[k % 8 + 1]})
end

local lua_seconds = os.clock() - t0

local img, stats = scene:render{width = 1280, height = 720,
                                samples = tonumber(arg and arg[3]) or 1}
if out then img:save(out, {encoding = "linear"}) end
-- One machine-readable line for tools/bench/bench.lua.
local rays = 0
for _, n in pairs(stats.rays) do rays = rays + n end
io.stderr:write(("bench b2 N=%d " ..
  "lua=%.4f build=%.4f trace=%.4f rays=%d nodes=%d prims=%d\n"):format(
  N, lua_seconds, stats.compile_seconds, stats.trace_seconds, rays, stats.bvh_nodes,
  stats.primitives))
