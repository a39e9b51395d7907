-- Seed report, figure 8: "Pixels take the colour of the object a ray hits
-- only if the point hit is lit (with coefficients). The yellow and cyan
-- spheres are the light sources."
--
-- Figure 7's scene with the n.l coefficient back on (the default) and a
-- second, cyan light sphere. Each sphere light of radiance L and radius r
-- gives a diffuse point at distance d the radiance kd * C * L * (r/d)^2 * cos:
-- with L = 50 and r = 0.3, tops of the spheres read ~1, the floor right
-- under a light ~0.5, and it falls off with the square of the distance.
-- Where both lights reach, yellow + cyan adds up to white-green.
local lancer = require "lancer"

local function diffuse(rgb) return lancer.material{color = rgb} end

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 3.4, 8}, at = {0, 0.6, 0}, fov = 52},
  background = 0,
}

scene:add(lancer.sphere{center = {-0.8, 2.7, 1.3}, radius = 0.3,
                        material = lancer.material{kd = 0, emission = {50, 50, 0}}})
scene:add(lancer.sphere{center = {2.9, 2.0, 1.0}, radius = 0.3,
                        material = lancer.material{kd = 0, emission = {0, 50, 50}}})

scene:add(lancer.quad{corner = {-4, 0, 3}, u = {8, 0, 0}, v = {0, 0, -6},
                      material = diffuse{1, 1, 1}})
scene:add(lancer.sphere{center = {-1.9, 0.8, 0.2}, radius = 0.8, material = diffuse{1, 0, 0}})
scene:add(lancer.sphere{center = {1.7, 0.7, -0.6}, radius = 0.7, material = diffuse{0, 1, 0}})
scene:add(lancer.sphere{center = {0.5, 0.45, 1.6}, radius = 0.45, material = diffuse{1, 0, 1}})
scene:add(lancer.box{min = {-0.5, 0, -2.2}, max = {0.5, 1, -1.2}, material = diffuse{1, 1, 1}})

-- The seed's lights: one ray toward each glowing sphere's centre, hard
-- shadows (light_samples = 0); leave it out for soft shadows.
local img = scene:render{width = 400, height = 300, light_samples = 0}
img:save(arg and arg[1] or "fig08.png")
