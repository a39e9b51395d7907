-- mixed.lua: N objects scattered on a ground plane, by turns a sphere, a
-- box, an open cylinder, a leaning quad and a triangle (one mesh holds the
-- triangles); one light.
-- Usage: lancer scenes/bench/mixed.lua [N] [out.png]   (N = 50000)
-- tools/bench/scenes.lua's M.mixed says the same for POV-Ray and Tachyon.
local lancer = require "lancer"
local N = tonumber(arg and arg[1]) or 50000
local out = arg and arg[2]
local t0 = os.clock()

local s = 13                           -- the benchmark's LCG, seeded
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
local meshes = {}                     -- the triangles, a mesh per material
for k = 0, N - 1 do
  local x, z, r = -50 + 100 * u(), -50 + 100 * u(), 0.15 + 0.4 * u()
  local m, kind = mats[k % 8 + 1], k % 5
  if kind == 0 then
    scene:add(lancer.sphere{center = {x, r, z}, radius = r, material = m})
  elseif kind == 1 then
    scene:add(lancer.box{min = {x - r, 0, z - r}, max = {x + r, 1.5 * r, z + r}, material = m})
  elseif kind == 2 then
    scene:add(lancer.cylinder{base = {x, 0, z}, top = {x, 2.5 * r, z}, radius = 0.6 * r,
                              caps = false, material = m})
  elseif kind == 3 then
    scene:add(lancer.quad{corner = {x - r, 0, z}, u = {2 * r, 0, 0}, v = {0, 2 * r, r},
                          material = m})
  else
    local t = meshes[m] or {vertices = {}, faces = {}}
    meshes[m] = t
    local v, f, n = t.vertices, t.faces, #t.vertices
    v[n + 1], v[n + 2], v[n + 3] = x - r, 0, z
    v[n + 4], v[n + 5], v[n + 6] = x + r, 0, z
    v[n + 7], v[n + 8], v[n + 9] = x, 2 * r, z + 0.3 * r
    local i = n // 3
    f[#f + 1], f[#f + 2], f[#f + 3] = i + 1, i + 2, i + 3
  end
end
for _, m in ipairs(mats) do
  local t = meshes[m]
  if t then
    scene:add(lancer.mesh{vertices = t.vertices, faces = t.faces, material = m})
  end
end
local lua_seconds = os.clock() - t0

local img, stats = scene:render{width = 1280, height = 720}
if out then img:save(out, {encoding = "linear"}) end
local rays = 0
for _, n in pairs(stats.rays) do rays = rays + n end
io.stderr:write(("bench mixed N=%d lua=%.4f build=%.4f trace=%.4f rays=%d nodes=%d " ..
  "prims=%d ntests=%d\n"):format(N, lua_seconds, stats.compile_seconds,
  stats.trace_seconds, rays, stats.bvh_nodes, stats.primitives, stats.node_tests))
