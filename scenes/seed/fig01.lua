-- Seed report, figure 1: "White pixels where a ray hits a sphere, black
-- where the ray hit nothing. Only spheres are present."
--
-- No lights: every sphere is emissive white with no diffuse term, so a hit
-- reads exactly 1 and a miss reads the black background.
local lancer = require "lancer"

local white = lancer.material{kd = 0, emission = 1}

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 0, 10}, at = {0, 0, 0}, fov = 50},
  background = 0,
}

-- A few spheres of different sizes and depths, two of them overlapping.
local spheres = {
  {{-2.6,  1.0, -1.0}, 1.3},
  {{-0.4, -0.6,  1.0}, 1.0},
  {{ 0.6, -0.2, -0.5}, 1.2},
  {{ 2.9,  1.3, -2.0}, 1.5},
  {{ 2.4, -1.9,  2.0}, 0.6},
  {{-3.1, -2.0,  1.0}, 0.5},
  {{ 0.3,  2.3, -3.0}, 0.7},
}
for _, s in ipairs(spheres) do
  scene:add(lancer.sphere{center = s[1], radius = s[2], material = white})
end

local img = scene:render{width = 400, height = 300}
img:save(arg and arg[1] or "fig01.png")
