-- Seed report, figure 10: "Absorbing colours: a magenta sphere lit in white
-- (above), the same sphere lit in red on one side and green on the other
-- (below)."
--
-- The light reflected is the light received times the object's colour.
-- Magenta (1, 0.1, 1) keeps red and blue: under white it reads magenta;
-- under red it reads red; under green it stays almost black, since it
-- absorbs nine tenths of the green.
--
-- Both halves share one scene, so a black, unlit quad in the plane y = 0
-- keeps the white light off the lower sphere and the red and green lights
-- off the upper one. The camera sits in that plane and sees it edge-on:
-- it never shows.
local lancer = require "lancer"

local magenta = lancer.material{color = {1, 0.1, 1}}
local function light(rgb) return lancer.material{kd = 0, emission = rgb} end

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 0, 8}, at = {0, 0, 0}, fov = 50},
  background = 0,
}

scene:add(lancer.quad{corner = {-20, 0, -20}, u = {40, 0, 0}, v = {0, 0, 26},
                      material = lancer.material{color = 0, kd = 0}})

-- Above: white light, in front. Nearest sphere point ~2.2 from it:
-- 110 * (0.2/2.2)^2 ~ 0.9.
scene:add(lancer.sphere{center = {0, 1.25, 0}, radius = 1, material = magenta})
scene:add(lancer.sphere{center = {1.0, 1.6, 3.0}, radius = 0.2, material = light(110)})

-- Below: red from the left, green from the right, each ~1.7 from the sphere.
scene:add(lancer.sphere{center = {0, -1.25, 0}, radius = 1, material = magenta})
scene:add(lancer.sphere{center = {-2.2, -1.25, 1.6}, radius = 0.2,
                        material = light{75, 0, 0}})
scene:add(lancer.sphere{center = {2.2, -1.25, 1.6}, radius = 0.2,
                        material = light{0, 75, 0}})

-- The seed's lights: one ray toward each glowing sphere's centre, hard
-- shadows (light_samples = 0); leave it out for soft shadows.
local img = scene:render{width = 400, height = 300, light_samples = 0}
img:save(arg and arg[1] or "fig10.png")
