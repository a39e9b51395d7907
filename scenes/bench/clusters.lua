-- clusters.lua: N spheres in 64 dense clusters, each a cube of side 3 to 7
-- whose spheres overlap many times over; a ground plane, one light.
-- Usage: lancer scenes/bench/clusters.lua [N] [out.png]   (N = 100000)
-- tools/bench/scenes.lua's M.clusters says the same for POV-Ray and Tachyon.
local lancer = require "lancer"
local N = tonumber(arg and arg[1]) or 100000
local out = arg and arg[2]
local t0 = os.clock()

local s = 11                           -- the benchmark's LCG, seeded
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
  camera = lancer.camera{from = {0, 30, 75}, at = {0, 2, 0}, fov = 60},
  background = {0.5, 0.7, 1.0}, ambient = 1, max_depth = 3}
scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
  material = lancer.material{color = 0.6, ka = 0.1, kd = 0.8, absorb = "diffuse"}})
scene:add(lancer.point_light{position = {40, 60, 30}, falloff = "none"})
local K, centres = 64, {}
for c = 1, K do
  local spread = 1.5 + 2 * u()
  centres[c] = {-40 + 80 * u(), spread + 1 + 4 * u(), -40 + 80 * u(), spread}
end
for k = 0, N - 1 do
  local c = centres[k % K + 1]
  local x = c[1] + c[4] * (2 * u() - 1)
  local y = c[2] + c[4] * (2 * u() - 1)
  local z = c[3] + c[4] * (2 * u() - 1)
  scene:add(lancer.sphere{center = {x, y, z}, radius = 0.15 + 0.35 * u(),
                          material = mats[k % 8 + 1]})
end
local lua_seconds = os.clock() - t0

local img, stats = scene:render{width = 1280, height = 720}
if out then img:save(out, {encoding = "linear"}) end
local rays = 0
for _, n in pairs(stats.rays) do rays = rays + n end
io.stderr:write(("bench clusters N=%d lua=%.4f build=%.4f trace=%.4f rays=%d nodes=%d " ..
  "prims=%d ntests=%d\n"):format(N, lua_seconds, stats.compile_seconds,
  stats.trace_seconds, rays, stats.bvh_nodes, stats.primitives, stats.node_tests))
