-- city.lua: a procedural city, as a script would build one: an L x L grid
-- of lots, every eighth row and column a street, a box a lot, its footprint
-- and height random, taller toward the middle; a ground plane, one light.
-- Usage: lancer scenes/bench/city.lua [L] [out.png]   (L = 160: 21 904 boxes)
-- tools/bench/scenes.lua's M.city says the same for POV-Ray and Tachyon.
local lancer = require "lancer"
local L = tonumber(arg and arg[1]) or 160
local out = arg and arg[2]
local t0 = os.clock()

local s = 7                           -- the benchmark's LCG, seeded
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
  camera = lancer.camera{from = {0, 0.3 * L, 0.6 * L}, at = {0, 0, 0}, fov = 50},
  background = {0.5, 0.7, 1.0}, ambient = 1, max_depth = 3}
scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
  material = lancer.material{color = 0.6, ka = 0.1, kd = 0.8, absorb = "diffuse"}})
scene:add(lancer.point_light{position = {0.4 * L, 0.6 * L, 0.25 * L}, falloff = "none"})
for i = 0, L - 1 do
  for j = 0, L - 1 do
    if i % 8 ~= 0 and j % 8 ~= 0 then
      local cx, cz = i - L / 2 + 0.5, j - L / 2 + 0.5
      local w, d = 0.55 + 0.4 * u(), 0.55 + 0.4 * u()
      local near = math.max(0, 1 - math.sqrt(cx * cx + cz * cz) / (L / 2))
      local h = 0.3 + 0.5 * u() + 12 * near * near * u()
      scene:add(lancer.box{min = {cx - w / 2, 0, cz - d / 2}, max = {cx + w / 2, h, cz + d / 2},
                           material = mats[(i * L + j) % 8 + 1]})
    end
  end
end
local lua_seconds = os.clock() - t0

local img, stats = scene:render{width = 1280, height = 720}
if out then img:save(out, {encoding = "linear"}) end
local rays = 0
for _, n in pairs(stats.rays) do rays = rays + n end
io.stderr:write(("bench city L=%d lua=%.4f build=%.4f trace=%.4f rays=%d nodes=%d " ..
  "prims=%d ntests=%d\n"):format(L, lua_seconds, stats.compile_seconds, stats.trace_seconds,
  rays, stats.bvh_nodes, stats.primitives, stats.node_tests))
