-- showcase.lua: one scene that uses every part of the lancer API.
--
-- A mirror ball in the middle of coloured Phong spheres, a glass ball, a
-- rotated box, two quads, an infinite checkered floor, two coloured point
-- lights, a glowing sphere that lights its surroundings, a little ambient
-- light, up to six bounces (in and out of the glass, off the mirrors).
--   build/bin/lancer scenes/showcase.lua [out.png]
local lancer = require "lancer"

local scene = lancer.scene{
  camera = lancer.camera{from = {0.6, 2.8, 9}, at = {0, 0.9, 0}, fov = 55},
  background = {0.16, 0.2, 0.3},      -- a dusky sky the mirrors can show
  ambient = 0.05,
  max_depth = 6,
}

-- Floor: an infinite plane of large soft tiles, slightly glossy.
local tiles = lancer.checker{a = {0.78, 0.75, 0.7}, b = {0.55, 0.52, 0.5}, scale = 1.5}
scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                       material = lancer.material{color = tiles, kd = 0.85, kr = 0.12}})

-- A glass ball on the right: it refracts the floor and the ring behind it.
scene:add(lancer.sphere{center = {1.45, 0.55, 2.9}, radius = 0.55,
                        material = lancer.material{kd = 0, ka = 0, ks = 0.6, alpha = 100,
                                                   kt = 0.95, ior = 1.5,
                                                   absorption = {0.15, 0.08, 0.02}}})

-- The mirror ball: almost all reflection, a sharp highlight.
scene:add(lancer.sphere{center = {0, 1.3, 0}, radius = 1.3,
                        material = lancer.material{color = {0.95, 0.95, 0.97}, kd = 0.04,
                                                   kr = 0.92, ks = 0.6, alpha = 300}})

-- Coloured spheres with Phong highlights. absorb = 'diffuse' keeps the
-- highlights white instead of tinting them with the sphere's colour.
local function plastic(rgb)
  return lancer.material{color = rgb, kd = 0.85, ks = 0.5, alpha = 60, absorb = 'diffuse'}
end
scene:add(lancer.sphere{center = {-3.3, 0.75, 0.9}, radius = 0.75,
                        material = plastic{0.85, 0.12, 0.1}})
scene:add(lancer.sphere{center = {3.1, 0.6, 1.5}, radius = 0.6,
                        material = plastic{0.12, 0.3, 0.85}})
scene:add(lancer.sphere{center = {2.4, 0.45, -2.0}, radius = 0.45,
                        material = plastic{0.15, 0.7, 0.2}})

-- A ring of small spheres round the mirror ball, their hue going round the
-- colour wheel; the ball shows the ones hidden behind it.
local function hue(h)             -- h in [0, 1) -> saturated rgb
  local function ch(k)
    local x = (h * 6 + k) % 6
    return math.max(0, math.min(1, math.abs(x - 3) - 1))
  end
  return {ch(0), ch(4), ch(2)}
end
local n = 14
for i = 0, n - 1 do
  local a = 2 * math.pi * i / n
  scene:add(lancer.sphere{center = {2.1 * math.cos(a), 0.22, 2.1 * math.sin(a)},
                          radius = 0.22, material = plastic(hue(i / n))})
end

-- A box turned 35 degrees about the vertical: its edges are rotated vectors.
local c, s = math.cos(math.rad(35)), math.sin(math.rad(35))
local size = 1.1
scene:add(lancer.box{corner = {-3.4, 0, -2.6},
                     u = {size * c, 0, size * s}, v = {0, size, 0},
                     w = {-size * s, 0, size * c},
                     material = lancer.material{color = {0.95, 0.6, 0.15}, kd = 0.9,
                                                ks = 0.3, alpha = 40}})

-- Two quads: a tall pale panel at the back right, a thin gold slab leaning
-- against the box.
scene:add(lancer.quad{corner = {1.0, 0, -3.6}, u = {2.8, 0, 0.9}, v = {0, 2.6, 0},
                      material = lancer.material{color = {0.7, 0.85, 0.9}, kd = 0.9}})
scene:add(lancer.quad{corner = {-2.3, 0, -0.8}, u = {0.9, 0, 0.5}, v = {-0.45, 1.0, -0.5},
                      material = lancer.material{color = {0.9, 0.75, 0.3}, kd = 0.6,
                                                 kr = 0.3, ks = 0.8, alpha = 80}})

-- Light 1: warm key light, up left. ~8.3 from the floor's centre, so
-- 55 / 8.3^2 = 0.8 head-on. Light 2: cool fill from the right.
scene:add(lancer.point_light{position = {-4, 6, 5}, color = {1, 0.85, 0.7}, intensity = 55})
scene:add(lancer.point_light{position = {6, 4, 3}, color = {0.55, 0.7, 1}, intensity = 28})

-- Light 3: a glowing orange orb on the floor in front. Its radiance is far
-- above 1 (it shows clamped); what it gives a surface d away is
-- L * (r/d)^2 * cos: 5 * (0.3 / 0.8)^2 = 0.7 at 0.8 from its centre.
scene:add(lancer.sphere{center = {-1.3, 0.3, 3.1}, radius = 0.3,
                        material = lancer.material{kd = 0, emission = {5, 1.6, 0.3}}})

local img, stats = scene:render{width = 800, height = 600, samples = 4, light_samples = 4}
img:save(arg and arg[1] or "showcase.png")
print(("showcase: %dx%d in %.2fs"):format(img.width, img.height, stats.seconds))
