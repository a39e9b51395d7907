-- 05_frames.lua: an animation is a loop that renders one image per frame.
--   build/bin/lancer examples/05_frames.lua [folder]
-- writes folder/frame_0001.png ... frame_0008.png (folder: "frames").
local lancer = require "lancer"

local dir = arg and arg[1] or "frames"
local frames = 8

-- Make the folder. The name goes to the shell inside single quotes, with
-- any quote in it escaped, so spaces and odd characters are safe.
local function shell_quote(s) return "'" .. s:gsub("'", [['\'']]) .. "'" end
assert(os.execute("mkdir -p " .. shell_quote(dir)), "cannot create " .. dir)

-- Build the scene for time t in [0, 1). Making a new scene each frame keeps
-- every frame independent: any frame can be rendered alone, in any order.
local function scene_at(t)
  local scene = lancer.scene{
    camera = lancer.camera{from = {0, 2, 6}, at = {0, 0.5, 0}, fov = 50},
    background = {0.05, 0.06, 0.1},
  }
  scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                         material = lancer.material{color = 0.5}})
  -- The ball goes round a circle and bounces twice per turn.
  local angle = 2 * math.pi * t
  local height = 0.5 + 1.2 * math.abs(math.sin(2 * angle))
  scene:add(lancer.sphere{center = {1.5 * math.cos(angle), height, 1.5 * math.sin(angle)},
                          radius = 0.5,
                          material = lancer.material{color = {0.9, 0.4, 0.1}, ks = 0.5}})
  scene:add(lancer.point_light{position = {-2, 5, 3}, intensity = 35})
  return scene
end

for frame = 1, frames do
  local img = scene_at((frame - 1) / frames):render{width = 160, height = 120}
  local path = ("%s/frame_%04d.png"):format(dir, frame)
  img:save(path)
  print("wrote " .. path)
end
