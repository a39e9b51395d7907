-- s7.lua: docs/numerics.md S7 "cost parity": a diffuse-only scene, 1024x1024 at
-- 4 spp, 1000 spheres and 1000 triangles, 2 point lights. Rendered by the
-- full lancer and by `make MINIMAL=1`'s (tools/bench/parity.lua).
-- Usage: lancer scenes/bench/s7.lua [out.png|-] [side] [samples] [threads]
local lancer = require "lancer"
local out = arg and arg[1]
if out == "-" then out = nil end       -- no image, but a side or samples follow
local SIDE = tonumber(arg and arg[2]) or 1024
local SPP = tonumber(arg and arg[3]) or 4
local THREADS = tonumber(arg and arg[4]) or 0           -- 0: one per core
local t0 = os.clock()   -- CPU time: building is single-threaded, so it is wall time too

-- The benchmark's PRNG (docs/bench-scenes.md: a 64-bit LCG, seed 1; Lua integers wrap).
local s = 1
local function u()
  s = s * 6364136223846793005 + 1442695040888963407
  return (s >> 11) * (1.0 / 9007199254740992.0)
end

-- Diffuse only: kd > 0, ks = kr = 0, no emission; ambient is allowed.
-- Both absorb modes, so both of shade.c's ways to apply C are priced.
local PALETTE = {{0.9, 0.2, 0.2}, {0.2, 0.9, 0.2}, {0.2, 0.3, 0.9}, {0.9, 0.9, 0.2},
                 {0.9, 0.2, 0.9}, {0.2, 0.9, 0.9}, {0.95, 0.95, 0.95}, {0.9, 0.5, 0.1}}
local mats = {}
for k, c in ipairs(PALETTE) do
  mats[k] = lancer.material{color = c, ka = 0.1, kd = 0.8, ks = 0, kr = 0,
                            absorb = k % 2 == 0 and "all" or "diffuse"}
end

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 22, 46}, at = {0, 2, -4}, fov = 62},
  background = {0.5, 0.7, 1.0}, ambient = 1}
-- One light falls off with the square of the distance, the other does not.
scene:add(lancer.point_light{position = {-30, 45, 35}, intensity = 4500})
scene:add(lancer.point_light{position = {40, 30, 10}, color = {1, 0.9, 0.8},
                             intensity = 0.45, falloff = "none"})

-- 1000 spheres resting on a ground region the camera sees whole: z in
-- [-8, 30], |x| up to 12 at the front, 35 at the back (no ground: every
-- primitive is a sphere or a triangle).
local sphere, add = lancer.sphere, scene.add
for k = 0, 999 do
  local z = -8 + 38 * u()
  local x = (2 * u() - 1) * (12 + 0.6 * (30 - z))
  local r = 0.4 + 1.0 * u()
  add(scene, sphere{center = {x, r, z}, radius = r, material = mats[k % 8 + 1]})
end

-- 1000 triangles: a separate field, a standing wall of tilted shards behind
-- the spheres (x in [-40, 40], y in [-2, 26], z in [-22, -12]), each its own
-- 3 vertices, lit from the front and shadowed by the spheres.
local meshes = {}
for k = 1, 8 do meshes[k] = lancer.mesh{material = mats[k]} end
local verts, faces = {}, {}
for k = 1, 8 do verts[k], faces[k] = {}, {} end
for k = 0, 999 do
  local cx, cy, cz = -40 + 80 * u(), -2 + 28 * u(), -22 + 10 * u()
  local v, f = verts[k % 8 + 1], faces[k % 8 + 1]
  local base = #v // 3
  for j = 0, 2 do
    -- A corner at angle 120 j degrees plus jitter, 1.5 to 3.5 from the
    -- centre, the wall's depth jittered by up to +-1.5.
    local a = (j + 0.6 * u()) * (2 * math.pi / 3)
    local d = 1.5 + 2 * u()
    v[#v + 1] = cx + d * math.cos(a)
    v[#v + 1] = cy + d * math.sin(a)
    v[#v + 1] = cz + 3 * u() - 1.5
  end
  f[#f + 1], f[#f + 2], f[#f + 3] = base + 1, base + 2, base + 3
end
for k = 1, 8 do
  meshes[k]:add_vertices(verts[k])
  meshes[k]:add_faces(faces[k])
  scene:add(meshes[k])
end

local lua_seconds = os.clock() - t0

local img, stats = scene:render{width = SIDE, height = SIDE, samples = SPP,
                                threads = THREADS}
-- With an output path, also a digest of the float image (FNV-1a over each
-- channel's bits): the PNG's 8 bits could hide a difference, this cannot
-- (but for a hash collision).
local digest = 0
if out then
  img:save(out, {encoding = "linear"})
  local pack, unpack, px = string.pack, string.unpack, img.pixel
  digest = 1469598103934665603
  for y = 1, SIDE do
    for x = 1, SIDE do
      local a, b, c = unpack("<I4I4I4", pack("<fff", px(img, x, y)))
      digest = ((((digest ~ a) * 1099511628211 ~ b) * 1099511628211) ~ c) * 1099511628211
    end
  end
end
-- One machine-readable line for tools/bench/bench.lua and parity.lua.
local rays = 0
for _, n in pairs(stats.rays) do rays = rays + n end
io.stderr:write(("bench s7 side=%d spp=%d " ..
  "lua=%.4f build=%.4f trace=%.4f rays=%d camera=%d shadow=%d reflection=%d " ..
  "ptests=%d ntests=%d threads=%d nodes=%d prims=%d digest=%d\n"):format(
  SIDE, SPP, lua_seconds, stats.compile_seconds, stats.trace_seconds, rays,
  stats.rays.camera, stats.rays.shadow, stats.rays.reflection, stats.prim_tests,
  stats.node_tests, stats.threads, stats.bvh_nodes, stats.primitives, digest))
