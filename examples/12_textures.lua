-- 12_textures.lua: textures: a checker floor to the horizon, marble, wood
-- rings, a bumpy ball, an image on a panel, and a mix of two patterns.
--   build/bin/lancer examples/12_textures.lua [out.png]
--
-- A texture stands where a colour or coefficient would; it is evaluated
-- only where its material is hit. Solid patterns (checker, marble, wood,
-- noise) live in space; the image lives on the panel's texture coordinates.
local lancer = require "lancer"

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 1.7, -6}, at = {0, 0.8, 0}, fov = 50},
  background = {0.55, 0.65, 0.8},
  ambient = 0.15,
}

-- A checker floor to the horizon: one plane, squares of 0.75.
local floor = lancer.checker{a = {0.85, 0.85, 0.8}, b = {0.2, 0.22, 0.25}, scale = 0.75}
scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                       material = lancer.material{color = floor, kr = 0.1}})

-- Marble veins through a sphere, and wood rings through a box.
local marble = lancer.marble{a = {0.95, 0.93, 0.9}, b = {0.35, 0.3, 0.35}, scale = 0.6,
                             turbulence = 1.5, octaves = 5}
scene:add(lancer.sphere{center = {-1.6, 0.7, 0.3}, radius = 0.7,
                        material = lancer.material{color = marble, ks = 0.5, alpha = 80,
                                                   absorb = "diffuse"}})
local wood = lancer.wood{a = {0.75, 0.5, 0.25}, b = {0.45, 0.25, 0.1}, scale = 0.08,
                         turbulence = 0.6}
scene:add(lancer.box{min = {-0.45, 0, -0.9}, max = {0.45, 0.9, 0},
                     material = lancer.material{color = wood:moved(lancer.translate(0, 0,
                                                                                  1.3))}})

-- A bumpy ball: noise as a height field bends its shading normal.
local dents = lancer.noise{scale = 0.12, octaves = 3}
scene:add(lancer.sphere{center = {1.6, 0.7, 0.3}, radius = 0.7,
                        material = lancer.material{color = {0.75, 0.2, 0.15}, ks = 0.6,
                                                   alpha = 60, absorb = "diffuse",
                                                   bump = dents, bump_scale = 0.015}})

-- An image on a panel at the back: a gradient drawn pixel by pixel, mixed
-- with stripes by a noise.
local img = lancer.image{width = 32, height = 16}
for y = 1, 16 do
  for x = 1, 32 do img:set(x, y, x / 32, 0.3 + 0.4 * y / 16, 1 - x / 32) end
end
local picture = lancer.image_texture{image = img}
local stripes = lancer.stripes{a = {1, 1, 1}, b = {0.1, 0.1, 0.1}, scale = 0.15,
                               axis = {1, 1, 0}}
local panel = lancer.mix{a = picture, b = stripes, amount = lancer.noise{scale = 0.5}}
scene:add(lancer.quad{corner = {2.4, 0.2, 2.5}, u = {-4.8, 0, 0}, v = {0, 2.4, 0},
                      material = lancer.material{color = panel, ka = 0.6, kd = 0.6}})

scene:add(lancer.point_light{position = {-3, 5, -4}, intensity = 45})
scene:add(lancer.point_light{position = {4, 3, -3}, color = {0.7, 0.8, 1}, intensity = 15})

local out, stats = scene:render{width = 320, height = 200, samples = 16}
out:save(arg and arg[1] or "12_textures.png")
print(("texture: %s"):format(stats.why.texture))
