-- cornell.lua: the Cornell box, with light that bounces.
--
-- The box as measured at Cornell (www.graphics.cornell.edu/online/box/data.html),
-- in its own millimetres over 10, as POV-Ray's radiosity example
-- (/usr/share/doc/povray/examples/radiosity/cornell.pov) writes it: the
-- same vertices, the same camera (35 mm lens, 39.5 degrees). The camera
-- looks down +z, so +x (the red wall) is on its left, as in the photograph.
-- Reflectances are the usual RGB fits of the measured spectra (pbrt's and
-- Mitsuba's versions of the scene), the light's radiance (17, 12, 4) theirs.
-- Only the light lights it: every other wall is lit by the bounces, which is
-- what `indirect` switches on; with indirect = 0 the walls facing away from
-- the light are black and nothing bleeds.
--   build/bin/lancer scenes/cornell.lua [out.png] [samples] [indirect]
-- loadfile("scenes/cornell.lua")("--scene") returns the scene, unrendered
-- (tools/bench/bounces.lua measures it); ("--data") the box as numbers.
local lancer = require "lancer"

-- The box as data, which tools/bench/cornell.lua also writes for POV-Ray:
-- camera, colours, the walls as meshes (vertices, faces, colour), the
-- blocks' top quads and heights, the light's quad and radiance.
local BOX = {
  camera = {from = {27.8, 27.3, -80}, at = {27.8, 27.3, 0}, fov = 39.5},
  colors = {white = {0.725, 0.71, 0.68}, red = {0.63, 0.065, 0.05},
            green = {0.14, 0.45, 0.091}},
  walls = {
    -- Floor, ceiling and back wall (white).
    {vertices = {{55.28, 0, 0}, {0, 0, 0}, {0, 0, 55.92}, {54.96, 0, 55.92},
                 {55.60, 54.88, 0}, {55.60, 54.88, 55.92}, {0, 54.88, 55.92}, {0, 54.88, 0}},
     faces = {{1, 2, 3}, {1, 3, 4}, {5, 6, 7}, {5, 7, 8}, {7, 6, 4}, {7, 4, 3}},
     color = "white"},
    -- Right wall (green, x = 0) and left wall (red, x = 55).
    {vertices = {{0, 54.88, 0}, {0, 54.88, 55.92}, {0, 0, 55.92}, {0, 0, 0}},
     faces = {{1, 2, 3}, {1, 3, 4}}, color = "green"},
    {vertices = {{55.28, 0, 0}, {54.96, 0, 55.92}, {55.60, 54.88, 55.92}, {55.60, 54.88, 0}},
     faces = {{1, 2, 3}, {1, 3, 4}}, color = "red"},
  },
  -- The two blocks (white): a top quad's corners at height h, sides down to 0.
  blocks = {
    {top = {{13.0, 6.5}, {8.2, 22.5}, {24.0, 27.2}, {29.0, 11.4}}, height = 16.5},
    {top = {{42.3, 24.7}, {26.5, 29.6}, {31.4, 45.6}, {47.2, 40.6}}, height = 33.0},
  },
  -- The light: 13 x 10.5 just under the ceiling, facing down.
  light = {corner = {21.3, 54.87, 22.7}, u = {13, 0, 0}, v = {0, 0, 10.5},
           radiance = {17, 12, 4}},
}

-- A block's mesh: the top quad, then the four sides.
function BOX.block_mesh(b)
  local v, f = {}, {}
  for i, p in ipairs(b.top) do
    v[i] = {p[1], b.height, p[2]}
    v[i + 4] = {p[1], 0, p[2]}
  end
  f[1] = {1, 2, 3, 4}
  for i = 1, 4 do
    local j = i % 4 + 1
    f[#f + 1] = {i, i + 4, j + 4, j}
  end
  return v, f
end

if ... == "--data" then return BOX end

local scene = lancer.scene{camera = lancer.camera(BOX.camera), max_depth = 8}
local materials = {}
for name, rgb in pairs(BOX.colors) do
  materials[name] = lancer.material{color = rgb, kd = 1}
end
for _, w in ipairs(BOX.walls) do
  scene:add(lancer.mesh{vertices = w.vertices, faces = w.faces,
                        material = materials[w.color]})
end
for _, b in ipairs(BOX.blocks) do
  local v, f = BOX.block_mesh(b)
  scene:add(lancer.mesh{vertices = v, faces = f, material = materials.white})
end
local L = BOX.light
scene:add(lancer.quad{corner = L.corner, u = L.u, v = L.v,
                      material = lancer.material{kd = 0, emission = L.radiance}})

if ... == "--scene" then return scene end

local out = arg and arg[1] or "out/cornell.png"
local samples = tonumber(arg and arg[2]) or 64
local indirect = tonumber(arg and arg[3]) or 8
local img, stats = scene:render{width = 256, height = 256, samples = samples,
                                indirect = indirect}
img:save(out, {tone = "filmic"})
print(("%s: %dx%d, %d samples, indirect %d, %.2f s; %d indirect rays"):format(out,
  img.width, img.height, samples, indirect, stats.seconds, stats.rays.indirect))
