-- 09_soft_glossy_lens.lua: the effects that need samples, and what they cost.
--   build/bin/lancer examples/09_soft_glossy_lens.lua [out.png]
--
-- A row of spheres on a brushed floor, lit by a glowing panel: the panel's
-- shadows are soft (it is sampled as an area light), the floor and the
-- middle sphere reflect through diffusion cones (glossiness), and a thin
-- lens keeps the middle sphere sharp while the others blur. Adaptive
-- sampling spends the samples where the noise is: the sky stops early.
-- The ledger printed at the end says what each effect cost in rays.
local lancer = require "lancer"

local scene = lancer.scene{
  -- aperture: the lens diameter; focus: the distance that stays sharp
  camera = lancer.camera{from = {0, 1.2, -6}, at = {0, 0.6, 0}, fov = 45,
                         aperture = 0.25, focus = 8.3},
  background = {0.55, 0.65, 0.85},
  ambient = 0.05,
}

-- A floor that reflects through a 5-degree cone: blurred reflections.
scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                       material = lancer.material{color = {0.75, 0.72, 0.68}, kd = 0.6,
                                                  kr = 0.35, glossiness = 5,
                                                  cone_samples = 8, absorb = "diffuse"}})

-- Spheres from near to far, in rainbow colours; the one at the focus
-- distance is a glossy mirror.
local function rainbow(t)
  local function c(phase) return 0.5 + 0.45 * math.cos(2 * math.pi * (t + phase)) end
  return {c(0), c(1 / 3), c(2 / 3)}
end
for i = -2, 4 do
  local m = lancer.material{color = rainbow((i + 2) / 7), ks = 0.4, alpha = 40}
  if i == 1 then
    m = lancer.material{color = 0.95, kd = 0.1, kr = 0.85, glossiness = 3, cone_samples = 8}
  end
  scene:add(lancer.sphere{center = {-1.1 * i, 0.6, 2.2 * i}, radius = 0.6, material = m})
end

-- The light: a glowing panel overhead, seen by the shading as an area light.
scene:add(lancer.quad{corner = {-1.5, 4, -1.5}, u = {3, 0, 0}, v = {0, 0, 3},
                      material = lancer.material{kd = 0, emission = 2.5}})

local img, stats = scene:render{
  width = 480, height = 270,
  samples = 64, noise = 0.05, min_samples = 8,  -- adaptive: up to 64 per pixel
  light_samples = 2,                            -- per hit; 8 per pixel at least
}
img:save(arg and arg[1] or "09_soft_glossy_lens.png")
print(lancer.ledger(stats))
