-- Seed report, figure 3: "Pixels take the colour of the object a ray hits,
-- and are black where the rays hit nothing. Intertwined planes and spheres
-- are present in the scene."
--
-- The seed's planes are bounded (parallelograms): lancer.quad. Flat colours
-- again (emissive, no diffuse term, no lights); the only depth cue is where
-- one object cuts through another.
local lancer = require "lancer"

local function flat(rgb)
  return lancer.material{kd = 0, emission = rgb}
end

local scene = lancer.scene{
  camera = lancer.camera{from = {0.5, 3.5, 10}, at = {0, -0.2, 0}, fov = 50},
  background = 0,
}

-- Left: a red sphere cut by a blue square tilted back through its centre.
scene:add(lancer.sphere{center = {-2.9, 0.3, 0}, radius = 1.1,
                        material = flat{0.9, 0.15, 0.1}})
scene:add(lancer.quad{corner = {-4.5, -0.9, 1.2}, u = {3.2, 0, 0}, v = {0, 2.4, -2.4},
                      material = flat{0.2, 0.4, 0.9}})

-- Middle: a green sphere pierced by a yellow panel turned 45 degrees.
scene:add(lancer.sphere{center = {0.2, -0.1, 0}, radius = 1.2,
                        material = flat{0.15, 0.75, 0.25}})
scene:add(lancer.quad{corner = {-0.9, -1.8, 1.1}, u = {0, 3.8, 0}, v = {2.2, 0, -2.2},
                      material = flat{0.95, 0.8, 0.1}})

-- Right: two panels crossing along a horizontal line, an orange ball
-- threaded on the crossing.
scene:add(lancer.quad{corner = {2.0, -1.3, 1.2}, u = {2.6, 0, 0}, v = {0, 2.6, -2.4},
                      material = flat{0.85, 0.25, 0.8}})
scene:add(lancer.quad{corner = {2.0, -1.3, -1.2}, u = {2.6, 0, 0}, v = {0, 2.6, 2.4},
                      material = flat{0.1, 0.75, 0.8}})
scene:add(lancer.sphere{center = {3.3, 0, 0}, radius = 0.6,
                        material = flat{1.0, 0.5, 0.1}})

-- A grey strip, lower than everything else, that all three groups sink into.
scene:add(lancer.quad{corner = {-5.2, -1.0, -2}, u = {10.4, 0, 0}, v = {0, 0, 4},
                      material = flat{0.45, 0.45, 0.45}})

local img = scene:render{width = 400, height = 300}
img:save(arg and arg[1] or "fig03.png")
