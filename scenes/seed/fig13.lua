-- Seed report, figure 13: "An example rendered with diffusion cones.
-- Duplicated reflections are visible in the image, showing the limits of
-- our implementation."
--
-- The seed's cone was a fixed pattern (concentric circles, the same rays
-- at every pixel), so a glossy surface showed a few sharp, shifted copies
-- of what it reflects. lancer draws the cone's rays from a stratified set
-- scrambled per pixel (glossiness: the cone's half-angle in degrees;
-- cone_samples: rays per glossy hit, weighted by the cosine and normalised
-- as in the seed): the reflections blur into one, with no copies.
-- Figure 12's spheres stand on a glossy floor; the mirror sphere is glossy.
local lancer = require "lancer"

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 1.6, 7}, at = {0, 0.8, 0}, fov = 50},
  background = 0,
  max_depth = 3,
}

scene:add(lancer.quad{corner = {-10, 0, 9}, u = {20, 0, 0}, v = {0, 0, -13},
                      material = lancer.material{color = 0.5, kd = 0.6, kr = 0.4,
                                                 glossiness = 4, cone_samples = 16}})
-- Behind the camera, unseen but for its image in the glossy sphere.
scene:add(lancer.quad{corner = {-10, 0, 9}, u = {20, 0, 0}, v = {0, 14, 0},
                      material = lancer.material{color = 0.5}})
scene:add(lancer.sphere{center = {-1.1, 1, 0}, radius = 1,
                        material = lancer.material{color = 1, kd = 0, kr = 1, ks = 1,
                                                   alpha = 20, glossiness = 8,
                                                   cone_samples = 16}})
scene:add(lancer.sphere{center = {1.3, 0.8, 0.8}, radius = 0.8,
                        material = lancer.material{color = {0, 1, 0}, kd = 1, kr = 0,
                                                   ks = 0}})
scene:add(lancer.point_light{position = {1.5, 4, 3}, color = {1, 0.55, 0.15},
                             intensity = 16})

local img = scene:render{width = 400, height = 300}
img:save(arg and arg[1] or "fig13.png")
