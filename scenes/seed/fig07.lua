-- Seed report, figure 7: "Pixels take the colour of the object a ray hits
-- only if the point hit is lit (without coefficient). The yellow sphere is
-- the light source."
--
-- The light is an emissive sphere; a point is lit when the ray from it
-- toward the light's centre meets the light first (the seed's shadow ray).
-- cosine = false drops the n.l factor, so a lit point is not shaded by its
-- angle to the light. The seed's light had no falloff either: here the
-- light is bright enough that even the farthest lit point gets more than
-- 1.0, so every lit point clamps to the object's colour times the light's,
-- flat. A yellow light carries no blue: the white floor and box read yellow,
-- the magenta ball reads red (figure 8 shows its blue).
local lancer = require "lancer"

local function diffuse(rgb) return lancer.material{color = rgb} end

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 3.4, 8}, at = {0, 0.6, 0}, fov = 52},
  background = 0,
}

-- Farthest lit floor point is ~7 away: 700 * (0.3 / 7)^2 = 1.3 > 1.
scene:add(lancer.sphere{center = {-0.8, 2.7, 1.3}, radius = 0.3,
                        material = lancer.material{kd = 0, emission = {700, 700, 0}}})

scene:add(lancer.quad{corner = {-4, 0, 3}, u = {8, 0, 0}, v = {0, 0, -6},
                      material = diffuse{1, 1, 1}})
scene:add(lancer.sphere{center = {-1.9, 0.8, 0.2}, radius = 0.8, material = diffuse{1, 0, 0}})
scene:add(lancer.sphere{center = {1.7, 0.7, -0.6}, radius = 0.7, material = diffuse{0, 1, 0}})
scene:add(lancer.sphere{center = {0.5, 0.45, 1.6}, radius = 0.45, material = diffuse{1, 0, 1}})
scene:add(lancer.box{min = {-0.5, 0, -2.2}, max = {0.5, 1, -1.2}, material = diffuse{1, 1, 1}})

local img = scene:render{width = 400, height = 300, cosine = false}
img:save(arg and arg[1] or "fig07.png")
