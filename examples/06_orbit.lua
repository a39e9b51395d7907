-- 06_orbit.lua: an animation. The seed's mirror box (figure 14) seen by a
-- camera that circles the room once while a red ball bounces across it.
--   build/bin/lancer examples/06_orbit.lua                  frames in out/
--   build/bin/lancer --video orbit.mp4 examples/06_orbit.lua    ... and a video
--   build/bin/lancer --frames 1-12 examples/06_orbit.lua    only frames 1 to 12
-- arg[1] replaces the output pattern (out/orbit_%04d.png).
--
-- lancer.animate calls `frame` once per frame with f.number (1..48),
-- f.clock (0 at the first frame, growing to 1 over the animation), f.time
-- (seconds) and f.index (0..47), and renders and saves what it returns.
-- Everything below is derived from f alone, so any frame can be rendered by
-- itself, in any order, on any machine, and comes out the same.
local lancer = require "lancer"

local function mat(rgb, kd, kr, ks)
  return lancer.material{color = rgb, kd = kd or 1, kr = kr or 0, ks = ks or 0, alpha = 40}
end

-- Made once: materials can be shared by every frame's scene.
local walls = mat({0.9, 0.9, 0.95}, 0.35, 0.6)
local red, blue = mat({0.9, 0.15, 0.1}, 0.9, 0, 0.4), mat({0.15, 0.3, 0.9}, 0.9, 0, 0.4)
local green, yellow = mat({0.2, 0.8, 0.25}, 0.9, 0, 0.4), mat({0.95, 0.8, 0.15}, 0.9)

local function room(f)
  -- The camera goes once round the middle of the room, looking at its centre.
  local a = 2 * math.pi * f.clock
  local scene = lancer.scene{
    camera = lancer.camera{from = {2.6 * math.sin(a), 0.9, 2.6 * math.cos(a)},
                           at = {0, -1.2, 0}, fov = 75},
    max_depth = 3,
  }
  scene:add(lancer.box{min = {-3, -2, -3}, max = {3, 2, 3}, material = walls})
  -- The red ball crosses the room and back, bouncing four times.
  local x = 1.8 * math.cos(a)
  local y = -1.6 + 1.6 * math.abs(math.sin(4 * a))
  scene:add(lancer.sphere{center = {x, y, -0.6}, radius = 0.4, material = red})
  scene:add(lancer.sphere{center = {1.3, -1.4, 0.8}, radius = 0.6, material = blue})
  scene:add(lancer.sphere{center = {-0.9, -1.55, 1.2}, radius = 0.45, material = green})
  local c, s = math.cos(math.rad(30)), math.sin(math.rad(30))
  scene:add(lancer.box{corner = {-0.4, -2, -1.7}, u = {0.9 * c, 0, -0.9 * s}, v = {0, 0.9, 0},
                       w = {0.9 * s, 0, 0.9 * c}, material = yellow})
  scene:add(lancer.point_light{position = {0, 1.2, 0.3}, intensity = 9})
  return scene
end

lancer.animate{
  frames = 48, fps = 24,
  loop = true,                        -- clock runs to 47/48: frame 48 leads back to frame 1
  output = arg and arg[1] or "out/orbit_%04d.png",
  render = {width = 320, height = 240, samples = 4},
  frame = room,
}
