-- 03_lights_and_shadows.lua: coloured lights, shadows, and a glowing sphere.
--   build/bin/lancer examples/03_lights_and_shadows.lua [out.png]
local lancer = require "lancer"

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 3, 7}, at = {0, 0.6, 0}, fov = 55},
  background = 0,
}

local white = lancer.material{color = 0.9}
scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}, material = white})
scene:add(lancer.sphere{center = {-1.2, 0.8, 0}, radius = 0.8, material = white})
scene:add(lancer.box{min = {0.6, 0, -0.9}, max = {1.8, 1.2, 0.3}, material = white})

-- Two point lights of different colours. Light adds up: where both reach,
-- orange + blue makes white; where an object hides one of them, its shadow
-- takes the colour of the other. A point is lit by a light only if nothing
-- stands between them (a "shadow ray" is traced to check).
-- Each is ~4.5 from the objects: 15 / 4.5^2 = 0.75.
scene:add(lancer.point_light{position = {-3, 4, 2}, color = {1, 0.6, 0.2}, intensity = 15})
scene:add(lancer.point_light{position = {3, 4, 2}, color = {0.2, 0.45, 1}, intensity = 15})

-- Any shape with emission > 0 glows and is a light too. A sphere of
-- radiance L and radius r gives a surface at distance d facing it
-- L * (r/d)^2. Here 0.9 from the floor below: 12 * (0.25/0.9)^2 = 0.9.
-- Seen directly, 12 is far above 1 and shows clamped: the red and blue are
-- kept below 1 so it still looks green. kd = 0: it only shines, unlit.
-- It is a solid ball too, so it casts shadows from the point lights.
-- As a light it is sampled over its area (16 points per lit point by
-- default, render{light_samples = ...}), so its shadows are soft.
scene:add(lancer.sphere{center = {0.2, 0.9, 1.8}, radius = 0.25,
                        material = lancer.material{kd = 0, emission = {0.3, 12, 0.6}}})

local img = scene:render{width = 320, height = 240}
img:save(arg and arg[1] or "03_lights_and_shadows.png")
