-- Seed report, figure 14: "A scene of objects inside a cube with mirror
-- faces. 3 bounces are considered for reflection."
--
-- The camera stands inside the room, a box seen from within. Its walls are
-- mostly mirror (kr = 0.6) with some diffuse (kd = 0.35) so they show the
-- light too. Objects repeat from wall to wall until max_depth = 3 stops
-- the recursion: the third reflection shows only the walls' diffuse light.
local lancer = require "lancer"

local function mat(rgb, kd, kr, ks)
  return lancer.material{color = rgb, kd = kd or 1, kr = kr or 0, ks = ks or 0, alpha = 40}
end

local scene = lancer.scene{
  camera = lancer.camera{from = {0.4, 0.5, 2.6}, at = {-0.2, -0.6, -1}, fov = 75},
  background = 0,
  max_depth = 3,
}

scene:add(lancer.box{min = {-3, -2, -3}, max = {3, 2, 3},
                     material = mat({0.9, 0.9, 0.95}, 0.35, 0.6)})

scene:add(lancer.sphere{center = {-1.2, -1.2, -1.0}, radius = 0.8,
                        material = mat({0.9, 0.15, 0.1}, 0.9, 0, 0.4)})
scene:add(lancer.sphere{center = {1.3, -1.4, -0.2}, radius = 0.6,
                        material = mat({0.15, 0.3, 0.9}, 0.9, 0, 0.4)})
scene:add(lancer.sphere{center = {0.5, -0.2, -1.8}, radius = 0.45,
                        material = mat({0.2, 0.8, 0.25}, 0.9, 0, 0.4)})
-- A yellow cube turned 30 degrees about the vertical: edge vectors u, v, w.
local c, s = math.cos(math.rad(30)), math.sin(math.rad(30))
scene:add(lancer.box{corner = {-0.2, -2, -0.3}, u = {0.9 * c, 0, -0.9 * s}, v = {0, 0.9, 0},
                     w = {0.9 * s, 0, 0.9 * c}, material = mat({0.95, 0.8, 0.15}, 0.9)})

-- The floor is 2.5 below the light: 7 / 2.5^2 = 1.1 head-on; the ceiling,
-- 1.5 above, gets 3.1 but keeps only kd = 0.35 of it.
scene:add(lancer.point_light{position = {0, 0.5, 0.3}, intensity = 7})

local img = scene:render{width = 400, height = 300}
img:save(arg and arg[1] or "fig14.png")
