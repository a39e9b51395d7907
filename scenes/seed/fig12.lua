-- Seed report, figure 12: "A white sphere with coefficients (0, 1, 1) and a
-- green sphere (1, 0, 0), lit by an orange light, with a specular highlight
-- on the mirror sphere." The tuples are (kd, kr, ks).
--
-- Figure 11 plus the Phong term ks * (R.V)^alpha * light on the mirror: the
-- point light itself cannot be seen in a mirror, its highlight can. A low
-- alpha spreads it into the seed's diffuse orange glow.
local lancer = require "lancer"

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 1.6, 7}, at = {0, 0.8, 0}, fov = 50},
  background = 0,
  max_depth = 3,
}

scene:add(lancer.quad{corner = {-10, 0, 9}, u = {20, 0, 0}, v = {0, 0, -13},
                      material = lancer.material{color = 0.5}})
-- Behind the camera, unseen but for its image in the mirror.
scene:add(lancer.quad{corner = {-10, 0, 9}, u = {20, 0, 0}, v = {0, 14, 0},
                      material = lancer.material{color = 0.5}})
scene:add(lancer.sphere{center = {-1.1, 1, 0}, radius = 1,
                        material = lancer.material{color = 1, kd = 0, kr = 1, ks = 1,
                                                   alpha = 20}})
scene:add(lancer.sphere{center = {1.3, 0.8, 0.8}, radius = 0.8,
                        material = lancer.material{color = {0, 1, 0}, kd = 1, kr = 0,
                                                   ks = 0}})
scene:add(lancer.point_light{position = {1.5, 4, 3}, color = {1, 0.55, 0.15},
                             intensity = 16})

local img = scene:render{width = 400, height = 300}
img:save(arg and arg[1] or "fig12.png")
