-- instances.lua: one torus mesh of 1024 triangles placed G x G times, each
-- turned about y and tilted about x, scaled and set on a ground plane; one
-- light. The mesh is stored once; each placing is an instance.
-- Usage: lancer scenes/bench/instances.lua [G] [out.png]   (G = 20: 400 tori)
-- tools/bench/scenes.lua's M.instances says the same for POV-Ray and Tachyon.
local lancer = require "lancer"
local G = tonumber(arg and arg[1]) or 20
local out = arg and arg[2]
local t0 = os.clock()
local sin, cos = math.sin, math.cos

local s = 17                           -- the benchmark's LCG, seeded
local function u()
  s = s * 6364136223846793005 + 1442695040888963407
  return (s >> 11) * (1.0 / 9007199254740992.0)
end

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 1.2 * G, 2.6 * G}, at = {0, 0, 0}, fov = 60},
  background = {0.5, 0.7, 1.0}, ambient = 1, max_depth = 3}
scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
  material = lancer.material{color = 0.6, ka = 0.1, kd = 0.8, absorb = "diffuse"}})
scene:add(lancer.point_light{position = {2 * G, 3 * G, 1.5 * G}, falloff = "none"})

-- The torus: 32 x 16 quads, two triangles each, around +y (radii 1, 0.35).
local SEG, RING = 32, 16
local vertices, faces = {}, {}
for i = 0, SEG - 1 do
  local a = 2 * math.pi * i / SEG
  for j = 0, RING - 1 do
    local b = 2 * math.pi * j / RING
    local r = 1 + 0.35 * cos(b)
    local n = #vertices
    vertices[n + 1], vertices[n + 2], vertices[n + 3] = r * cos(a), 0.35 * sin(b), r * sin(a)
  end
end
for i = 0, SEG - 1 do
  for j = 0, RING - 1 do
    local v00 = i * RING + j + 1
    local v10 = (i + 1) % SEG * RING + j + 1
    local v01 = i * RING + (j + 1) % RING + 1
    local v11 = (i + 1) % SEG * RING + (j + 1) % RING + 1
    local n = #faces
    faces[n + 1], faces[n + 2], faces[n + 3] = v00, v10, v11
    faces[n + 4], faces[n + 5], faces[n + 6] = v00, v11, v01
  end
end
local torus = lancer.mesh{vertices = vertices, faces = faces,
  material = lancer.material{color = {0.2, 0.3, 0.9}, ka = 0.1, kd = 0.8, absorb = "diffuse"}}
for i = 0, G - 1 do
  for j = 0, G - 1 do
    local a, b = 2 * math.pi * u(), 0.5 * math.pi * u()
    local sc = 0.6 + 0.6 * u()
    local x = (i - G / 2 + 0.5) * 4 + u() - 0.5
    local z = (j - G / 2 + 0.5) * 4 + u() - 0.5
    local ca, sa, cb, sb = cos(a), sin(a), cos(b), sin(b)
    scene:add(torus:moved(lancer.transform{          -- sc Ry(a) Rx(b), up to 1.4 sc
      {sc * ca, sc * sa * sb, sc * sa * cb, x},
      {0, sc * cb, -sc * sb, 1.4 * sc},
      {-sc * sa, sc * ca * sb, sc * ca * cb, z}}))
  end
end
local lua_seconds = os.clock() - t0

local img, stats = scene:render{width = 1280, height = 720}
if out then img:save(out, {encoding = "linear"}) end
local rays = 0
for _, n in pairs(stats.rays) do rays = rays + n end
io.stderr:write(("bench instances G=%d lua=%.4f build=%.4f trace=%.4f rays=%d nodes=%d " ..
  "prims=%d ntests=%d\n"):format(G, lua_seconds, stats.compile_seconds,
  stats.trace_seconds, rays, stats.bvh_nodes, stats.primitives, stats.node_tests))
