-- b3.lua: B3 "mesh" of docs/bench-scenes.md: a Q x Q terrain, 2 triangles a quad.
-- Usage: lancer scenes/bench/b3.lua Q [out.png]   (Q = 707: 1M triangles; 1414: 4M)
local lancer = require "lancer"
local Q = tonumber(arg and arg[1]) or 100
local out = arg and arg[2]
local t0 = os.clock()   -- CPU time: building is single-threaded, so it is wall time too
local sin, cos = math.sin, math.cos

local function h(x, z)
  return 3.0 * sin(0.11 * x) * cos(0.13 * z) + 1.2 * sin(0.37 * x + 1.0) * sin(0.29 * z + 2.0)
       + 0.35 * sin(1.3 * x + 0.3) * cos(1.7 * z + 0.7) + 0.1 * sin(5.1 * x) * cos(4.3 * z)
end

local mesh = lancer.mesh{material = lancer.material{color = {0.55, 0.65, 0.40}, ka = 0.1,
                                                    kd = 0.8, absorb = "diffuse"}}
-- Row by row through the flat-array fast path: the Lua side never holds
-- more than one row, whatever Q.
for j = 0, Q do
  local row, n = {}, 0
  local z = -50 + 100 * j / Q
  for i = 0, Q do
    local x = -50 + 100 * i / Q
    row[n + 1], row[n + 2], row[n + 3] = x, h(x, z), z
    n = n + 3
  end
  mesh:add_vertices(row)
end
for j = 0, Q - 1 do
  local row, n = {}, 0
  for i = 0, Q - 1 do
    local v00 = j * (Q + 1) + i + 1          -- 1-based, as Lua counts
    local v10, v01 = v00 + 1, v00 + Q + 1
    local v11 = v01 + 1
    row[n + 1], row[n + 2], row[n + 3] = v00, v10, v11
    row[n + 4], row[n + 5], row[n + 6] = v00, v11, v01
    n = n + 6
  end
  mesh:add_faces(row)
end

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 14, 62}, at = {0, 0, 0}, fov = 60},
  background = {0.5, 0.7, 1.0}, ambient = 1}
scene:add(mesh)
scene:add(lancer.point_light{position = {60, 25, 20}, falloff = "none"})
local lua_seconds = os.clock() - t0

local img, stats = scene:render{width = 1280, height = 720}
if out then img:save(out, {encoding = "linear"}) end
-- One machine-readable line for tools/bench/bench.lua.
local rays = 0
for _, n in pairs(stats.rays) do rays = rays + n end
io.stderr:write(("bench b3 Q=%d " ..
  "lua=%.4f build=%.4f trace=%.4f rays=%d nodes=%d prims=%d\n"):format(
  Q, lua_seconds, stats.compile_seconds, stats.trace_seconds, rays, stats.bvh_nodes,
  stats.primitives))
