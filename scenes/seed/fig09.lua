-- Seed report, figure 9: "Adding colours: a white sphere lit by two light
-- sources, a green one and a red one."
--
-- Light colours add (and are clamped only at output): where both lights
-- reach the sphere, red + green reads yellow. The lights are small emissive
-- spheres; one of radiance L and radius r lights a white diffuse point at
-- distance d with L * (r/d)^2 * cos. With r = 0.25 the nearest points are
-- ~1.9 away, so L = 75 makes them read ~1.0 (a little over, clamped).
local lancer = require "lancer"

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 0.3, 8}, at = {0, 0, 0}, fov = 50},
  background = 0,
}

scene:add(lancer.sphere{center = {0, 0, 0}, radius = 1.2,
                        material = lancer.material{color = 1}})
scene:add(lancer.sphere{center = {-2.0, 1.0, 2.2}, radius = 0.25,
                        material = lancer.material{kd = 0, emission = {75, 0, 0}}})
scene:add(lancer.sphere{center = {2.0, 1.0, 2.2}, radius = 0.25,
                        material = lancer.material{kd = 0, emission = {0, 75, 0}}})

-- The seed's lights: one ray toward each glowing sphere's centre, hard
-- shadows (light_samples = 0); leave it out for soft shadows.
local img = scene:render{width = 400, height = 300, light_samples = 0}
img:save(arg and arg[1] or "fig09.png")
