-- test_anim.lua: lancer.animate and the command's frame options (--frames,
-- --frame, --shard, --skip-existing, --list-frames, -o, --video).
local T = require "harness"
local lancer = require "lancer"
local anim = require "lancer.anim"

local q = T.quote
local L = q(T.lancer)

local temp_dir = T.temp_dir

local function rm(dir) os.execute("rm -rf " .. q(dir)) end

local write = T.write
local check_exit = T.check_exit
local has = T.has

local function lines(s)
  local t = {}
  for l in s:gmatch("[^\n]+") do t[#t + 1] = l end
  return t
end

-- A 12-frame animation whose pixels depend on the frame: a sphere goes
-- round, jittered samples, and math.random moves the light. FAIL=n makes
-- frame n fail; arg[1] is the output pattern.
local ANIM = [[
local lancer = require "lancer"
lancer.animate{
  frames = 12, fps = 12, output = arg[1],
  render = {width = 24, height = 16, samples = 4},
  frame = function(f)
    if f.number == tonumber(os.getenv("FAIL") or -1) then error("frame " .. f.number .. " broke") end
    local s = lancer.scene{camera = lancer.camera{from = {0, 1, -5}, at = {0, 0, 0}}}
    local a = 2 * math.pi * f.clock
    s:add(lancer.sphere{center = {math.cos(a), 0, math.sin(a)}, radius = 1})
    s:add(lancer.point_light{position = {2 + math.random(), 4, -3}, intensity = 25})
    return s
  end}
]]

-- A folder holding the animation script; returns it and the script's path.
local function setup()
  local dir = temp_dir()
  write(dir .. "/anim.lua", ANIM)
  return dir, dir .. "/anim.lua"
end

-- The frame numbers --list-frames prints for these options.
local function listed(opts)
  local dir, script = setup()
  local out, err, code = T.run(("%s --list-frames %s %s %s"):format(
    L, opts, q(script), q(dir .. "/f_%04d.png")))
  rm(dir)
  check_exit(code, 0, out, err)
  local nums = {}
  for _, l in ipairs(lines(out)) do
    T.eq(l:sub(1, #dir), dir, "listed path")
    nums[#nums + 1] = tonumber(l:match("f_(%d+)%.png$"))
  end
  return table.concat(nums, ",")
end

T.test("--frames and --shard select exact frame lists", function()
  for _, c in ipairs{
    {"", "1,2,3,4,5,6,7,8,9,10,11,12"},
    {"--frames 7", "7"},
    {"--frame 5 --frame 7", "5,7"},
    {"--frames 3-6", "3,4,5,6"},
    {"--frames 1-12:4", "1,5,9"},
    {"--frames 1-12:3,2,11", "1,2,4,7,10,11"},
    {"--frames 1,5,9-12", "1,5,9,10,11,12"},
    {"--frames 1-4,3-6", "1,2,3,4,5,6"},
    {"--frames=10-12 --frames 1", "1,10,11,12"},
    {"--shard 0/2", "2,4,6,8,10,12"},
    {"--shard 1/3", "1,4,7,10"},
    {"--shard 0/1", "1,2,3,4,5,6,7,8,9,10,11,12"},
    {"--shard 4/5", "4,9"},
    {"--frames 2-9 --shard 0/2", "2,4,6,8"},
    {"--frames 1-12:2 --shard=1/4", "1,5,9"},
    {"--frames 12 --shard 0/5", ""},
  } do
    T.eq(listed(c[1]), c[2], "frames for '" .. c[1] .. "'")
  end
end)

T.test("bad frame options exit 2 with one line naming the flag", function()
  local dir, script = setup()
  for _, c in ipairs{
    {"--frames x", "option '--frames' needs frames like 7, 1-48, 1-48:2 or 1,5,9-12, got 'x'"},
    {"--frames 9-5", "got '9-5' (a range A-B needs A <= B)"},
    {"--frames 1-4:0", "got '1-4:0' (a step is a whole number from 1)"},
    {"--frames 1,,2", "got '1,,2'"},
    {"--frames -3", "got '-3'"},
    {"--frames 1-", "got '1-' (a range is A-B)"},
    {"--frames 99999999999", "got '99999999999'"},
    {"--frame 1-3", "option '--frame' needs one frame number (--frames takes lists), got '1-3'"},
    {"--shard 2/2", "option '--shard' needs K/N with 0 <= K < N, such as 0/4, got '2/2'"},
    {"--shard 1", "got '1'"},
    {"--shard 0/0", "got '0/0'"},
    {"--video out.avi", "option '--video' needs a file ending in .mp4, .mkv, .mov, .webm or .gif, got 'out.avi'"},
    {"-o out.png", "option '-o' needs a pattern with a frame field"},
    {"--skip-existing=yes", "option '--skip-existing' takes no value"},
    {"--frames", "option '--frames' needs a value", alone = true},
    {"--video", "option '--video' needs a value", alone = true},
  } do
    local out, err, code = T.run(("%s %s %s"):format(L, c[1], c.alone and "" or q(script)))
    check_exit(code, 2, out, err)
    T.eq(err:sub(1, 16), "lancer: option '", c[1])
    has(err, c[2], c[1])
    has(err, "; try 'lancer --help'", c[1])
    T.eq(#lines(err), 1, "lines on stderr for " .. c[1])
    T.eq(out, "", "stdout for " .. c[1])
  end
  rm(dir)
end)

T.test("--frames outside the animation, or no animation, exit 2", function()
  local dir, script = setup()
  local out, err, code = T.run(("%s --frames 10-14 %s %s"):format(L, q(script),
    q(dir .. "/f_%04d.png")))
  check_exit(code, 2, out, err)
  T.eq(err, "lancer: option '--frames': 10-14 is outside the animation's frames 1-12; " ..
       "try 'lancer --help'\n", "stderr")
  -- named as typed: --frame, not --frames
  out, err, code = T.run(("%s --frames 2 --frame 30 %s %s"):format(L, q(script),
    q(dir .. "/f_%04d.png")))
  check_exit(code, 2, out, err)
  T.eq(err, "lancer: option '--frame': frame 30 is outside the animation's frames 1-12; " ..
       "try 'lancer --help'\n", "stderr for --frame 30")
  local plain = dir .. "/plain.lua"
  write(plain, "print('no animation here')\n")
  out, err, code = T.run(("%s --shard 0/2 %s"):format(L, q(plain)))
  check_exit(code, 2, out, err)
  has(err, "lancer: option '--shard' needs a script that calls lancer.animate{...}; " ..
      plain .. " does not")
  rm(dir)
end)

T.test("frame options on a still script: exit 2 before anything is written", function()
  local dir = temp_dir()
  local still, blank = dir .. "/still.lua", dir .. "/blank.lua"
  write(still, [[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 0, -3}, at = {0, 0, 0}}}
s:add(lancer.sphere{center = {0, 0, 0}, radius = 1})
s:render{width = 8, height = 8}:save(arg[1])
print("rendered")
]])
  write(blank, "require('lancer').image{width = 2, height = 2}:save(arg[1])\n")
  for _, c in ipairs{{"--frame 3", still, "renders"}, {"--list-frames", still, "renders"},
                     {"--shard 0/2", blank, "saves an image"}} do
    local out, err, code = T.run(("%s %s %s %s"):format(L, c[1], q(c[2]),
                                                        q(dir .. "/x.png")))
    assert(not io.open(dir .. "/x.png"), c[1] .. ": x.png written")
    T.eq(out, "", c[1] .. ": stdout")
    check_exit(code, 2, out, err)
    T.eq(err, ("lancer: option '%s' needs a script that calls lancer.animate{...}; " ..
               "%s %s outside one; try 'lancer --help'\n"):format(c[1]:match("^%S+"),
               c[2], c[3]), c[1] .. ": stderr")
  end
  rm(dir)
end)

T.test("one log line per frame; a failed frame fails the run after the others", function()
  local dir, script = setup()
  local out, err, code = T.run(("FAIL=3 %s --frames 2-5 %s %s"):format(L, q(script),
    q(dir .. "/f_%04d.png")))
  check_exit(code, 1, out, err)
  local log = lines(err)
  T.eq(#log, 5, "stderr lines:\n" .. err)
  for i, n in ipairs{2, 4, 5} do
    local line = log[i < 2 and i or i + 1]
    local num, w, h, spp, secs, rays, path = line:match(
      "^frame (%d+): (%d+)x(%d+), (%d+) spp, (%d+%.%d%d%d) s, (%d+) rays %-> (.+)$")
    assert(num, "log line has not the expected shape: " .. line)
    T.eq(tonumber(num), n, "frame number")
    T.eq(w .. "x" .. h .. " " .. spp, "24x16 4", "size and spp")
    assert(tonumber(rays) >= 24 * 16 * 4, "rays counted: " .. line)
    T.eq(path, ("%s/f_%04d.png"):format(dir, n), "path")
    assert(io.open(path), path .. " not written")
  end
  T.eq(log[2], "frame 3: FAILED: " .. script .. ":6: frame 3 broke", "failure line")
  T.eq(log[5], "lancer: animate: 1 of 4 frames failed (3)", "summary")
  assert(not io.open(dir .. "/f_0003.png"), "failed frame left a file")
  rm(dir)
end)

T.test("a frame rendered alone is byte-identical to the same frame in the sequence", function()
  local dir, script = setup()
  local out, err, code = T.run(("%s %s %s"):format(L, q(script), q(dir .. "/all_%02d.png")))
  check_exit(code, 0, out, err)
  for _, n in ipairs{1, 7, 12} do
    out, err, code = T.run(("%s --frame %d %s %s"):format(L, n, q(script),
      q(dir .. "/one_##.png")))
    check_exit(code, 0, out, err)
    local a = T.slurp(("%s/all_%02d.png"):format(dir, n))
    local b = T.slurp(("%s/one_%02d.png"):format(dir, n))
    assert(a and b and #a > 0, "frame " .. n .. " missing")
    assert(a == b, "frame " .. n .. " differs when rendered alone")
  end
  -- and the frames do differ from one another
  assert(T.slurp(dir .. "/all_01.png") ~= T.slurp(dir .. "/all_02.png"), "frames all alike")
  rm(dir)
end)

T.test("--skip-existing keeps finished frames and redoes a killed job's", function()
  local dir, script = setup()
  local pat = dir .. "/f_%04d.png"
  write(dir .. "/f_0002.png", "finished earlier")
  -- A job killed while writing frame 3 leaves only its temporary file.
  write(dir .. "/f_0003.png.tmp-AbC123", "half a PNG")
  local out, err, code = T.run(("%s --skip-existing --list-frames --frames 1-4 %s %s"):format(
    L, q(script), q(pat)))
  check_exit(code, 0, out, err)
  T.eq(out, ("%s/f_0001.png\n%s/f_0003.png\n%s/f_0004.png\n"):format(dir, dir, dir),
       "frames still to render")
  out, err, code = T.run(("%s --skip-existing --frames 1-4 %s %s"):format(L, q(script), q(pat)))
  check_exit(code, 0, out, err)
  local log = lines(err)
  T.eq(log[2], ("frame 2: skipped, %s/f_0002.png exists"):format(dir), "skip line")
  assert(log[3]:match("^frame 3: 24x16, 4 spp"), "frame 3 not rendered: " .. err)
  T.eq(T.slurp(dir .. "/f_0002.png"), "finished earlier", "skipped frame untouched")
  T.eq(T.slurp(dir .. "/f_0003.png"):sub(2, 4), "PNG", "frame 3")
  rm(dir)
end)

T.test("-o replaces the script's pattern and missing folders are created", function()
  local dir, script = setup()
  local out, err, code = T.run(("%s -o %s --frames 4 %s %s"):format(L,
    q(dir .. "/new/deep/r_####.png"), q(script), q(dir .. "/f_%04d.png")))
  check_exit(code, 0, out, err)
  assert(io.open(dir .. "/new/deep/r_0004.png"), "frame not written under -o:\n" .. err)
  assert(not io.open(dir .. "/f_0004.png"), "the script's pattern was used")
  rm(dir)
end)

-- ---- lancer.animate in this process -----------------------------------------

local function tiny_scene()
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, -3}, at = {0, 0, 0}}}
  s:add(lancer.sphere{center = {0, 0, 0}, radius = 1})
  return s
end

-- Runs lancer.animate with stderr silenced and these frame options (what
-- lancer.host gives lancer.anim under the lancer command).
local function animate(spec, options)
  local saved_options, saved_err = anim.options, io.stderr
  anim.options = options or {}
  io.stderr = {write = function() end, flush = function() end}
  local ok, res = pcall(lancer.animate, spec)
  anim.options, io.stderr = saved_options, saved_err
  if not ok then error(res, 0) end
  return res
end

T.test("animate: f has number, index, clock and time from the whole range", function()
  local dir = temp_dir()
  local seen = {}
  local res = animate({frames = 5, fps = 10, output = dir .. "/f_%d.png",
    render = {width = 4, height = 4},
    frame = function(f)
      seen[#seen + 1] = ("%d %d %.2f %.2f %d-%d"):format(f.number, f.index, f.clock, f.time,
                                                        f.first, f.last)
      return tiny_scene()
    end})
  T.eq(table.concat(seen, "|"), "1 0 0.00 0.00 1-5|2 1 0.25 0.10 1-5|3 2 0.50 0.20 1-5|" ..
       "4 3 0.75 0.30 1-5|5 4 1.00 0.40 1-5", "frames")
  T.eq(res.rendered, 5, "rendered")
  seen = {}
  animate({frames = 4, first = 0, loop = true, output = dir .. "/g_%d.png",
    render = {width = 4, height = 4},
    frame = function(f)
      seen[#seen + 1] = ("%d %.2f %.4f"):format(f.number, f.clock, f.time)
      return tiny_scene()
    end}, {frames = {{2, 3, 1}}})
  T.eq(table.concat(seen, "|"), "2 0.50 0.0833|3 0.75 0.1250", "loop, first = 0, frames 2-3")
  assert(io.open(dir .. "/g_0.png") == nil, "frame 0 rendered though not selected")
  assert(io.open(dir .. "/g_3.png"), "g_3.png")
  rm(dir)
end)

T.test("animate: Lua state persists; math.random is keyed by the frame", function()
  local dir = temp_dir()
  local calls, draws = 0, {}
  local spec = {frames = 3, output = dir .. "/f_%d.png", render = {width = 2, height = 2},
    frame = function(f)
      calls = calls + 1
      draws[f.number] = math.random()
      return tiny_scene(), {samples = 1}
    end}
  animate(spec)
  T.eq(calls, 3, "one call per frame, state kept")
  local all2 = draws[2]
  animate(spec, {frames = {{2, 2, 1}}})
  T.eq(calls, 4, "calls")
  T.eq(draws[2], all2, "math.random in frame 2 alone")
  assert(draws[1] ~= draws[2], "frames draw the same numbers")
  rm(dir)
end)

T.test("animate: an interrupt stops the animation at once", function()
  local dir = temp_dir()
  local calls = 0
  local ok, err = pcall(animate, {frames = 5, output = dir .. "/f_%d.png",
    frame = function(f)
      calls = calls + 1
      if f.number == 2 then error("stdin:1: render cancelled") end
      return tiny_scene(), {width = 2, height = 2}
    end})
  assert(not ok, "no error")
  has(tostring(err), "render cancelled")
  T.eq(calls, 2, "frames tried")
  rm(dir)
end)

T.test("animate: errors name the field at the caller's line", function()
  local f = function() return tiny_scene() end
  T.check_error(function() lancer.animate{fps = 24, output = "x_%d.png", frame = f} end,
    "test_anim.lua:", "bad argument #1 to 'animate'", "field 'frames': required")
  T.check_error(function() lancer.animate{frames = 0, output = "x_%d.png", frame = f} end,
    "test_anim.lua:", "field 'frames': must be in [1, 1000000000], got 0")
  T.check_error(function() lancer.animate{frames = 2.5, output = "x_%d.png", frame = f} end,
    "test_anim.lua:", "field 'frames': integer expected, got 2.5")
  T.check_error(function() lancer.animate{frames = 2, fps = -1, output = "x_%d.png", frame = f} end,
    "test_anim.lua:", "field 'fps': positive number expected, got -1")
  T.check_error(function() lancer.animate{frames = 2, output = "x.png", frame = f} end,
    "test_anim.lua:", "field 'output': needs a frame field such as %04d or ####, got 'x.png'")
  T.check_error(function() lancer.animate{frames = 2, output = "x_%d_%d.png", frame = f} end,
    "test_anim.lua:", "field 'output': needs exactly one frame field")
  T.check_error(function() lancer.animate{frames = 2, output = "x_%d.png"} end,
    "test_anim.lua:", "field 'frame': function expected, got nil")
  T.check_error(function()
    lancer.animate{frames = 2, output = "x_%d.png", frame = f, render = {frame = 3}} end,
    "test_anim.lua:", "field 'render': 'frame' is set by animate")
  T.check_error(function() lancer.animate{frames = 2, output = "x_%d.png", frame = f, fsp = 2} end,
    "test_anim.lua:", "unknown field 'fsp'")
  T.check_error(function() lancer.animate("x") end,
    "test_anim.lua:", "bad argument #1 to 'animate' (table expected, got string)")
end)

T.test("animate: output patterns, printf or Blender style", function()
  local cases = {
    {"out/f_%04d.png", 7, "out/f_0007.png", "out/f_%04d.png"},
    {"f%d.png", 12, "f12.png", "f%d.png"},
    {"100%%_%03d.png", 5, "100%_005.png", "100%%_%03d.png"},
    {"r_####.png", 42, "r_0042.png", "r_%04d.png"},
    {"50%_##.png", 3, "50%_03.png", "50%%_%02d.png"},
  }
  for _, c in ipairs(cases) do
    local path, ff = anim.pattern(c[1])
    assert(path, c[1] .. ": " .. tostring(ff))
    T.eq(path(c[2]), c[3], c[1])
    T.eq(ff, c[4], c[1] .. " for ffmpeg")
  end
  for _, bad in ipairs{"x.png", "x_%s.png", "x_%4d.png", "a_%d_##.png", "a##_##.png"} do
    assert(not anim.pattern(bad), bad .. " accepted")
  end
end)

-- ---- Video -----------------------------------------------------------------

local function have(cmd)
  return os.execute("command -v " .. cmd .. " >/dev/null 2>&1") == true
end

T.test("--video without ffmpeg: a clear message before any render, exit 1", function()
  local dir, script = setup()
  local bin = dir .. "/bin"              -- a PATH with sh but no ffmpeg
  os.execute(("mkdir %s && ln -s \"$(command -v sh)\" %s/sh"):format(q(bin), q(bin)))
  local out, err, code = T.run(("PATH=%s %s --video %s %s %s"):format(q(bin), L,
    q(dir .. "/v.mp4"), q(script), q(dir .. "/f_%04d.png")))
  check_exit(code, 1, out, err)
  has(err, "lancer: video: ffmpeg is not installed (Debian: apt-get install ffmpeg)")
  has(err, "ffmpeg -nostdin -y -loglevel error -framerate 12 -start_number 1 -i '" ..
      dir .. "/f_%04d.png' -frames:v 12")
  assert(not err:find("frame 1:", 1, true), "rendered before failing:\n" .. err)
  rm(dir)
end)

T.test("--video refuses to assemble when a frame is missing", function()
  if not have("ffmpeg") then T.skip("ffmpeg is not installed") end
  local dir, script = setup()
  local out, err, code = T.run(("FAIL=6 %s --video %s %s %s"):format(L,
    q(dir .. "/v.mp4"), q(script), q(dir .. "/f_%04d.png")))
  check_exit(code, 1, out, err)
  has(err, "lancer: animate: 1 of 12 frames failed (6)")
  assert(not io.open(dir .. "/v.mp4"), "video written with a frame missing")
  os.remove(dir .. "/f_0009.png")
  out, err, code = T.run(("%s --frames 1-5 --video %s %s %s"):format(L,
    q(dir .. "/v.mp4"), q(script), q(dir .. "/f_%04d.png")))
  check_exit(code, 1, out, err)
  has(err, "lancer: video: 2 of 12 frames missing, not assembling " .. dir ..
      "/v.mp4 (first missing: " .. dir .. "/f_0006.png)")
  rm(dir)
end)

-- The README's one command: a 48-frame animation to an mp4.
T.test("--video: the 48-frame orbit example becomes a 48-frame mp4 and a gif", function()
  if not have("ffmpeg") then T.skip("ffmpeg is not installed") end
  local dir = temp_dir()
  local out, err, code = T.run(("%s --width 32 --height 24 --samples 1 --video %s " ..
    "examples/06_orbit.lua %s"):format(L, q(dir .. "/orbit.mp4"), q(dir .. "/orbit_%04d.png")))
  check_exit(code, 0, out, err)
  T.eq(#lines(err), 49, "log lines")
  has(err, "video: " .. dir .. "/orbit.mp4, 48 frames at 24 fps")
  local probe = ("ffprobe -v error -count_frames -select_streams v:0 -show_entries " ..
    "stream=codec_name,width,height,nb_read_frames -of csv=p=0 %s")
  local p = assert(io.popen(probe:format(q(dir .. "/orbit.mp4"))))
  local info = p:read("a")
  p:close()
  T.eq(info, "h264,32,24,48\n", "ffprobe")
  out, err, code = T.run(("%s --skip-existing --video %s examples/06_orbit.lua %s"):format(
    L, q(dir .. "/orbit.gif"), q(dir .. "/orbit_%04d.png")))
  check_exit(code, 0, out, err)
  p = assert(io.popen(probe:format(q(dir .. "/orbit.gif"))))
  info = p:read("a")
  p:close()
  T.eq(info, "gif,32,24,48\n", "ffprobe gif")
  rm(dir)
end)
