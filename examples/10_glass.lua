-- 10_glass.lua: glass, after Whitted's 1980 picture: a glass sphere and a
-- mirror sphere over a tiled floor.
--   build/bin/lancer examples/10_glass.lua [out.png]
--
-- The glass refracts by Snell's law and reflects and transmits by the
-- Fresnel equations (more at grazing angles, so its rim shines); inside it
-- absorbs a little red and green, so its thick middle looks blue. Its
-- shadow is filtered: lighter than the mirror's, tinted like the glass.
-- A glass needs depth: in and out is 2 bounces, each reflection inside one
-- more (max_depth counts them all).
local lancer = require "lancer"

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 1.6, -5.5}, at = {0.2, 0.8, 0}, fov = 45},
  background = {0.45, 0.6, 0.85},
  ambient = 0.1,
  max_depth = 8,
}

-- The floor: 10 x 10 tiles in two colours.
local white = lancer.material{color = {0.9, 0.88, 0.8}, ka = 0.5}
local red = lancer.material{color = {0.8, 0.15, 0.1}, ka = 0.5}
for i = -5, 4 do
  for j = -3, 6 do
    scene:add(lancer.quad{corner = {i, 0, j}, u = {1, 0, 0}, v = {0, 0, 1},
                          material = (i + j) % 2 == 0 and white or red})
  end
end

-- Clear glass: no diffuse or ambient term, a highlight, and an index of
-- refraction; absorption is per unit of length travelled inside.
local glass = lancer.material{kd = 0, ka = 0, ks = 0.6, alpha = 80, kt = 1, ior = 1.5,
                              absorption = {0.25, 0.12, 0.02}}
scene:add(lancer.sphere{center = {-0.7, 1, 0}, radius = 1, material = glass})

local mirror = lancer.material{kd = 0.05, ka = 0, kr = 0.9, ks = 0.5, alpha = 60}
scene:add(lancer.sphere{center = {1.4, 0.7, 1.2}, radius = 0.7, material = mirror})

scene:add(lancer.point_light{position = {-3, 6, -4}, intensity = 70})

local img, stats = scene:render{width = 320, height = 200, samples = 4}
img:save(arg and arg[1] or "10_glass.png")
print(("%d refraction rays, %d reflection rays; refract: %s"):format(
  stats.rays.refraction, stats.rays.reflection, stats.why.refract))
