-- Seed report, figure 11: "A white sphere with coefficients (0, 1) and a
-- green sphere (1, 0), lit by an orange light." The pairs are (kd, kr).
--
-- The white sphere is a pure mirror (no diffuse light of its own): it shows
-- the green sphere and its surroundings. A grey floor and a wall behind the
-- camera, not in the caption, give it something to reflect besides black.
-- The orange light is a point light: a white surface facing it at distance
-- d reads intensity / d^2. A point light has no surface, so the mirror
-- cannot show it (figure 12 adds its highlight).
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
                        material = lancer.material{color = 1, kd = 0, kr = 1}})
scene:add(lancer.sphere{center = {1.3, 0.8, 0.8}, radius = 0.8,
                        material = lancer.material{color = {0, 1, 0}, kd = 1, kr = 0}})
-- The green sphere's top is ~3.3 away: 16 * 0.55 / 3.3^2 = 0.8 in green.
scene:add(lancer.point_light{position = {1.5, 4, 3}, color = {1, 0.55, 0.15},
                             intensity = 16})

local img = scene:render{width = 400, height = 300}
img:save(arg and arg[1] or "fig11.png")
