-- Seed report, figure 2: "Pixels take the colour of the object a ray hits,
-- and are black where the ray hit nothing. Only spheres are present."
--
-- No lights: each sphere emits its own colour and has no diffuse term, so
-- every pixel of a sphere is exactly that colour (no shading).
local lancer = require "lancer"

local function flat(rgb)
  return lancer.material{kd = 0, emission = rgb}
end

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 0, 10}, at = {0, 0, 0}, fov = 50},
  background = 0,
}

-- The layout of figure 1, now in colour.
local spheres = {
  {{-2.6,  1.0, -1.0}, 1.3, {0.9, 0.1, 0.1}},   -- red
  {{-0.4, -0.6,  1.0}, 1.0, {0.1, 0.7, 0.2}},   -- green
  {{ 0.6, -0.2, -0.5}, 1.2, {0.15, 0.3, 0.9}},  -- blue
  {{ 2.9,  1.3, -2.0}, 1.5, {0.95, 0.8, 0.1}},  -- yellow
  {{ 2.4, -1.9,  2.0}, 0.6, {0.8, 0.2, 0.8}},   -- magenta
  {{-3.1, -2.0,  1.0}, 0.5, {0.1, 0.8, 0.8}},   -- cyan
  {{ 0.3,  2.3, -3.0}, 0.7, {1.0, 0.5, 0.1}},   -- orange
}
for _, s in ipairs(spheres) do
  scene:add(lancer.sphere{center = s[1], radius = s[2], material = flat(s[3])})
end

local img = scene:render{width = 400, height = 300}
img:save(arg and arg[1] or "fig02.png")
