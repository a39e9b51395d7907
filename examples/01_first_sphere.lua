-- 01_first_sphere.lua: the smallest useful scene.
--   build/bin/lancer examples/01_first_sphere.lua [out.png]
--
-- A scene needs three things: a camera, something to see, and light.
local lancer = require "lancer"

-- The camera stands at `from` and looks at `at`. y is up. fov is the
-- horizontal field of view in degrees.
local camera = lancer.camera{from = {0, 1, 5}, at = {0, 0.5, 0}, fov = 50}

-- Every constructor takes one table of named fields. `background` is what
-- a ray that hits nothing sees: here a dark blue. Colours are {r, g, b},
-- linear, 0 to 1 (or one number for a grey).
local scene = lancer.scene{camera = camera, background = {0.05, 0.07, 0.12}}

-- A sphere: centre, radius, and a material. The material's colour says
-- which part of the light the surface sends back: this one keeps red.
local red = lancer.material{color = {0.9, 0.2, 0.15}}
scene:add(lancer.sphere{center = {0, 0.5, 0}, radius = 1, material = red})

-- A point light. Its light falls off with the square of the distance: a
-- white surface facing it at distance d reads intensity / d^2. This one is
-- about 4.5 from the sphere, so intensity 20 gives 20 / 4.5^2 = 1.0.
scene:add(lancer.point_light{position = {-3, 4, 3}, intensity = 20})

-- render returns the image (and statistics, unused here); save writes a PNG.
local img = scene:render{width = 320, height = 240}
img:save(arg and arg[1] or "01_first_sphere.png")
