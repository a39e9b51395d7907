-- 14_shapes.lua: the shapes POV-Ray users build with: cylinders, cones, a
-- disc and a ring, a torus, ellipsoids, each exact under any transform.
--   build/bin/lancer examples/14_shapes.lua [out.png]
--
-- Each is a canonical shape (a unit cylinder, cone, disc, torus or sphere)
-- placed by an affine map: a ray is solved in the shape's own space, so a
-- sheared or stretched one stays exact. The torus's quartic is solved by
-- bracketing its roots between critical points and refining in long double.
local lancer = require "lancer"

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 2.6, -7}, at = {0, 0.8, 0}, fov = 48},
  background = {0.2, 0.24, 0.3},
  ambient = 0.15,
  max_depth = 2,
}
scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                       material = lancer.material{color = {0.6, 0.6, 0.55}, kr = 0.1}})

local function paint(r, g, b)
  return lancer.material{color = {r, g, b}, ks = 0.5, alpha = 60, absorb = "diffuse"}
end

-- A column on a base: a capped cylinder on a truncated cone on a disc.
scene:add(lancer.disc{center = {-2.6, 0.01, 0.5}, normal = {0, 1, 0}, radius = 0.8,
                      material = paint(0.3, 0.3, 0.35)},
          lancer.cone{base = {-2.6, 0.01, 0.5}, top = {-2.6, 0.3, 0.5}, base_radius = 0.6,
                      top_radius = 0.35, material = paint(0.85, 0.85, 0.8)},
          lancer.cylinder{base = {-2.6, 0.3, 0.5}, top = {-2.6, 2.0, 0.5}, radius = 0.25,
                          material = paint(0.85, 0.85, 0.8)})

-- A torus standing on edge, and a thin ring lying flat around a cone.
scene:add(lancer.torus{center = {-0.4, 0.95, 0.8}, axis = {1, 0, 0.3}, major = 0.7,
                       minor = 0.22, material = paint(0.8, 0.35, 0.1)})
scene:add(lancer.cone{base = {1.2, 0, -0.6}, top = {1.2, 1.2, -0.6}, base_radius = 0.45,
                      top_radius = 0, material = paint(0.2, 0.5, 0.85)})
scene:add(lancer.disc{center = {1.2, 0.4, -0.6}, normal = {0, 1, 0}, radius = 0.75,
                      inner_radius = 0.55, material = paint(0.9, 0.75, 0.2)})

-- Ellipsoids: one by its radii, one a sphere sheared by a transform.
scene:add(lancer.ellipsoid{center = {2.7, 0.5, 0.8}, radii = {0.45, 0.5, 0.9},
                           material = paint(0.25, 0.7, 0.3)})
local shear = lancer.transform{{1, 0.6, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}
scene:add(lancer.sphere{center = {0, 0, 0}, radius = 0.45, material = paint(0.7, 0.2, 0.6)}
          :moved(shear):moved(lancer.translate(0.9, 0.45, 1.8)))

scene:add(lancer.point_light{position = {-3, 6, -5}, intensity = 60})
scene:add(lancer.point_light{position = {4, 3, -2}, color = {0.6, 0.7, 1}, intensity = 12})

local img = scene:render{width = 320, height = 200, samples = 4}
img:save(arg and arg[1] or "14_shapes.png")
