-- 08_moving.lua: transforms, a group, one mesh placed many times, keyframes.
--   build/bin/lancer examples/08_moving.lua out.png [t]     (t in [0, 1], default 0.3)
local lancer = require "lancer"

local out = arg and arg[1] or "moving.png"
local t = tonumber(arg and arg[2]) or 0.3

local scene = lancer.scene{
  camera = lancer.camera{from = {0, 4, -9}, at = {0, 0.5, 0}, fov = 50},
  background = {0.05, 0.06, 0.1}, ambient = 0.05,
}
scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                       material = lancer.material{color = 0.6, kr = 0.2}})

-- One octahedron mesh, stored once, placed twelve times round a ring.
local gem = lancer.mesh{
  vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}},
  faces = {{1, 3, 5}, {3, 2, 5}, {2, 4, 5}, {4, 1, 5}, {3, 1, 6}, {2, 3, 6}, {4, 2, 6}, {1, 4, 6}},
  material = lancer.material{color = {0.3, 0.6, 0.9}, ks = 0.6, alpha = 60},
}
for k = 0, 11 do
  local angle = 30 * k + 90 * t
  -- read right to left: shrink, spin, push out to radius 3, turn round the ring
  scene:add(gem:moved(lancer.rotate("y", angle) * lancer.translate(3, 0.4, 0)
                      * lancer.rotate("y", 4 * angle) * lancer.scale(0.3, 0.4, 0.3)))
end

-- A lamp: a glowing bulb and its light move together as a group, along keyframes.
local lamp = lancer.group{
  lancer.sphere{center = {0, 0, 0}, radius = 0.25, material = lancer.material{emission = 4}},
  lancer.point_light{position = {0, -0.4, 0}, intensity = 12},   -- below: no shadow of the bulb on the floor it lights
}
local path = lancer.keyframes{{0, {-2, 2.5, 0}}, {0.5, {0, 1.5, -1}, "ease_in_out"},
                              {1, {2, 2.5, 0}, "ease_in_out"}}
local p = path(t)
scene:add(lamp:moved(lancer.translate(p[1], p[2], p[3])))
scene:add(lancer.point_light{position = {-4, 6, -5}, intensity = 40})

for _, o in ipairs(scene:objects()) do
  if o.kind ~= "mesh" then print(o) end     -- the twelve gems would be a long list
end
scene:render{width = 480, height = 320, samples = 4}:save(out)
