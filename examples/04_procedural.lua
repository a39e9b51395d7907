-- 04_procedural.lua: a scene is a Lua program, so loops and maths build it.
--   build/bin/lancer examples/04_procedural.lua [out.png]
--
-- A spiral staircase of spheres: each one turns a little further round,
-- climbs a little higher and shifts its colour.
local lancer = require "lancer"

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 4.5, 10}, at = {0, 1.5, 0}, fov = 50},
  background = {0.04, 0.04, 0.06},
  ambient = 0.08,
}

scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                       material = lancer.material{color = 0.5}})

-- A colour from a number t in [0, 1]: three cosines a third of a turn apart.
local function rainbow(t)
  local function c(phase) return 0.5 + 0.5 * math.cos(2 * math.pi * (t + phase)) end
  return {c(0), c(1 / 3), c(2 / 3)}
end

local n = 30
for i = 0, n - 1 do
  local t = i / (n - 1)                    -- 0 for the first sphere, 1 for the last
  local angle = t * 3 * 2 * math.pi        -- three full turns
  local radius = 2.5 - 1.5 * t             -- spiralling inwards
  local size = 0.35 - 0.15 * t             -- and getting smaller
  scene:add(lancer.sphere{
    center = {radius * math.cos(angle), size + 3.2 * t, radius * math.sin(angle)},
    radius = size,
    material = lancer.material{color = rainbow(t), ks = 0.4, alpha = 40},
  })
end

scene:add(lancer.point_light{position = {-4, 7, 6}, intensity = 80})

local img = scene:render{width = 320, height = 240}
img:save(arg and arg[1] or "04_procedural.png")
