-- 15_lights_and_sky.lua: the lights people expect: a spot light's cone with
-- a soft edge, a low sun casting long parallel shadows, a sky gradient
-- behind, and a filmic tone curve so the bright pool does not clip.
--   build/bin/lancer examples/15_lights_and_sky.lua [out.png]
--
-- With indirect = 0 (the default) the sky is seen, not a light: it shows
-- behind and in mirrors. render{indirect = 4} would let it light the
-- scene too (the manual's "Light that bounces").
local lancer = require "lancer"

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 1.4, -7}, at = {0, 1.3, 0}, fov = 56},
  background = lancer.sky{zenith = {0.02, 0.07, 0.4}, horizon = {0.6, 0.62, 0.7},
                          ground = {0.25, 0.22, 0.2}},
  ambient = 0.08,
}

local floor = lancer.checker{a = {0.8, 0.78, 0.72}, b = {0.55, 0.52, 0.48}, scale = 1}
scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                       material = lancer.material{color = floor, ka = 1}})

-- A row of posts for the sun's shadows, a mirror ball showing the sky.
local wood = lancer.material{color = {0.7, 0.4, 0.25}, ka = 1}
for i = -2, 2 do
  scene:add(lancer.cylinder{base = {i * 1.2, 0, 1.5}, top = {i * 1.2, 1.6, 1.5}, radius = 0.12,
                            material = wood})
end
scene:add(lancer.sphere{center = {-1.6, 0.6, -0.6}, radius = 0.6,
                        material = lancer.material{kd = 0.1, kr = 0.85, ka = 0}})
scene:add(lancer.sphere{center = {1.2, 0.5, -0.8}, radius = 0.5,
                        material = lancer.material{color = {0.9, 0.9, 0.95}, ks = 0.4,
                                                   alpha = 40, ka = 1}})

-- A low sun from the left, warm; a spot from above right onto the white ball.
scene:add(lancer.directional_light{direction = {1, -0.35, 0.4}, irradiance = 2.2,
                                   color = {1, 0.85, 0.7}})
scene:add(lancer.spot_light{position = {2.5, 4, -2.5}, direction = {-1.3, -3.5, 1.7},
                            angle = 18, soft = 6, intensity = 22, color = {0.8, 0.9, 1}})

local out, stats = scene:render{width = 320, height = 200, samples = 4}
out:save(arg and arg[1] or "15_lights_and_sky.png", {tone = "filmic", exposure = 0.3})
print(("spot: %s; sun: %s; sky: %s"):format(stats.why.spot, stats.why.sun, stats.why.sky))
