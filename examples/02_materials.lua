-- 02_materials.lua: what a material's numbers do.
--   build/bin/lancer examples/02_materials.lua [out.png]
--
-- At each hit lancer adds up (the seed report's Phong model):
--   ka * ambient  +  kd * diffuse  +  ks * highlight  +  kr * mirror image
-- and multiplies by `color`. Five spheres, left to right:
local lancer = require "lancer"

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 2.4, 10}, at = {0, 0.7, 0}, fov = 55},
  background = {0.25, 0.3, 0.4},   -- a sky, so the mirrors have something to show
  ambient = 0.05,                  -- a little light everywhere, even in shadow
  max_depth = 3,                   -- mirror rays may bounce three times
}

-- The floor: an infinite plane through `point`, facing up.
scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                       material = lancer.material{color = 0.5}})

local materials = {
  -- 1. Diffuse (matte): kd = 1 is the default; bright where it faces the light.
  lancer.material{color = {0.2, 0.5, 0.9}},
  -- 2. Mirror: no diffuse light of its own, everything is reflection.
  lancer.material{color = 1, kd = 0, kr = 1},
  -- 3. Phong: diffuse plus a highlight. The bigger alpha, the smaller and
  --    sharper the highlight.
  lancer.material{color = {0.2, 0.8, 0.3}, kd = 0.8, ks = 0.6, alpha = 50},
  -- 4. A shiny red sphere, absorb = 'all' (the default, the seed's way): the
  --    colour multiplies everything, so the highlight and the reflections
  --    are red too, like coloured metal.
  lancer.material{color = {0.9, 0.15, 0.1}, kd = 0.5, kr = 0.4, ks = 0.8, alpha = 80,
                  absorb = 'all'},
  -- 5. The same numbers with absorb = 'diffuse': the colour multiplies only
  --    the ambient and diffuse light, so the highlight stays white and the
  --    reflections keep their colours, like varnished plastic.
  lancer.material{color = {0.9, 0.15, 0.1}, kd = 0.5, kr = 0.4, ks = 0.8, alpha = 80,
                  absorb = 'diffuse'},
}
for i, m in ipairs(materials) do
  scene:add(lancer.sphere{center = {(i - 3) * 2.1, 0.9, 0}, radius = 0.9, material = m})
end

-- One white light, up and to the left (~6 from the spheres: 36 / 6^2 = 1).
scene:add(lancer.point_light{position = {-3, 5, 4}, intensity = 36})

local img = scene:render{width = 320, height = 240}
img:save(arg and arg[1] or "02_materials.png")
