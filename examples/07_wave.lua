-- 07_wave.lua: a procedural animation. A field of spheres rides a ripple
-- spreading from the middle; each sphere's height and colour come from its
-- distance to the centre and the time.
--   build/bin/lancer examples/07_wave.lua                 out/wave_0001.png ...
--   build/bin/lancer --video wave.gif examples/07_wave.lua
-- arg[1] replaces the output pattern (out/wave_%04d.png).
local lancer = require "lancer"

local N = 11                  -- spheres per side
local SPACING = 0.55
local floor = lancer.material{color = 0.35}

-- A colour from a number t in [0, 1]: three cosines a third of a turn apart.
local function rainbow(t)
  local function c(phase) return 0.5 + 0.5 * math.cos(2 * math.pi * (t + phase)) end
  return {c(0), c(1 / 3), c(2 / 3)}
end

-- Materials are made once, 16 shades, and shared by every frame.
local shades = {}
for i = 0, 15 do
  shades[i] = lancer.material{color = rainbow(i / 16), ks = 0.5, alpha = 60}
end

local function wave(f)
  local scene = lancer.scene{
    camera = lancer.camera{from = {0, 4.2, -6.5}, at = {0, 0.2, 0}, fov = 55},
    background = {0.03, 0.03, 0.05},
    ambient = 0.1,
  }
  scene:add(lancer.plane{point = {0, -0.6, 0}, normal = {0, 1, 0}, material = floor})
  for i = 0, N - 1 do
    for j = 0, N - 1 do
      local x, z = (i - (N - 1) / 2) * SPACING, (j - (N - 1) / 2) * SPACING
      local d = math.sqrt(x * x + z * z)
      -- One wavelength every 1.6 units, moving outwards once per loop.
      local phase = 2 * math.pi * (d / 1.6 - f.clock)
      local h = 0.5 * math.sin(phase) * math.exp(-0.2 * d)
      local shade = math.floor(((phase / (2 * math.pi)) % 1) * 16)
      scene:add(lancer.sphere{center = {x, h, z}, radius = 0.22, material = shades[shade]})
    end
  end
  scene:add(lancer.point_light{position = {-3, 6, -4}, intensity = 60})
  scene:add(lancer.point_light{position = {4, 3, 2}, color = {0.4, 0.5, 1}, intensity = 12})
  return scene
end

lancer.animate{
  frames = 36, fps = 18, loop = true,
  output = arg and arg[1] or "out/wave_%04d.png",
  render = {width = 320, height = 240, samples = 4},
  frame = wave,
}
