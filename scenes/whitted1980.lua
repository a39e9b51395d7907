-- whitted1980.lua: Turner Whitted's 1980 picture ("An improved illumination
-- model for shaded display"): a glass sphere in front of a mirror sphere,
-- over a red and yellow checkerboard that stops short of the horizon, under
-- a blue sky.
--   build/bin/lancer scenes/whitted1980.lua [out.png]
--
-- What each part needs: the board is one quad with a checker texture (not
-- 1 600 quads); the glass sphere refracts by Snell's law with the Fresnel
-- weights and bends the board behind it upside down; the mirror shows the
-- board and the glass; max_depth 8 lets a ray in and out of the glass and
-- off the mirror; 16 samples smooth the checker's edges into the distance.
local lancer = require "lancer"

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 2.2, -6.5}, at = {-0.15, 1.1, 0}, fov = 42},
  background = {0.15, 0.35, 0.85},
  ambient = 0.25,
  max_depth = 8,
}

local board = lancer.checker{a = {0.95, 0.85, 0.1}, b = {0.9, 0.1, 0.05}, scale = 1}
scene:add(lancer.quad{corner = {-4, 0, -3}, u = {8, 0, 0}, v = {0, 0, 14},
                      material = lancer.material{color = board, ka = 0.4, kd = 0.8}})

-- Whitted's transparent sphere: clear glass with a bright highlight.
local glass = lancer.material{kd = 0, ka = 0, ks = 0.7, alpha = 120, kt = 0.95,
                              ior = 1.5, absorption = {0.08, 0.05, 0.02}}
scene:add(lancer.sphere{center = {0.45, 1.25, -0.6}, radius = 0.8, material = glass})

-- The mirror sphere, behind and to the right, a little of its own colour.
local mirror = lancer.material{color = {0.9, 0.9, 0.9}, kd = 0.1, ka = 0.05, kr = 0.85,
                               ks = 0.6, alpha = 80}
scene:add(lancer.sphere{center = {-1.05, 1.05, 1.4}, radius = 0.85, material = mirror})

scene:add(lancer.point_light{position = {-3, 8, -5}, intensity = 90})

local img = scene:render{width = 320, height = 240, samples = 16}
img:save(arg and arg[1] or "whitted1980.png")
