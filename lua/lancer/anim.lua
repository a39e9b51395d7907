-- lancer.anim: lancer.animate{...}, the animation driver. It renders the
-- frames the command line selects (--frames, --frame, --shard), skips those
-- already written (--skip-existing), lists paths (--list-frames), writes one
-- log line per frame on stderr, and assembles a video with ffmpeg (--video).
--
-- Frame n of an animation is the same image whether it is rendered alone
-- or within the whole sequence: its render gets frame = n (which keys every
-- random number of the renderer), math.random is reseeded with n before the
-- frame function runs, and f.clock and f.time come from the animation's
-- whole range, not from the frames selected.
local M = {count = 0, busy = false}   -- lancer.animate calls; in one now

-- What the command line selected: frames ({first, last, step, option}
-- triples, option naming the flag given), shard ({K, N}), skip_existing,
-- list_frames, video, output. lancer.host sets it for the lancer command;
-- elsewhere it is empty and every frame is rendered.
M.options = {}

-- lancer.host sets these for the lancer command: seed (--seed, which with
-- the frame number seeds math.random for each frame) and part_path (with
-- --tile or --region: where this run saves a frame's part, from the frame's
-- own path; --skip-existing and the log look for that file).
M.seed, M.part_path = nil, nil
local function target(path) return M.part_path and M.part_path(path) or path end

-- How a misuse of those options is reported: lancer.host makes it a usage
-- error (exit 2); elsewhere (lua5.4, tests) it is an error.
function M.usage(msg) error(msg, 0) end

local FIELDS = {"frames", "fps", "first", "output", "render", "frame", "loop"}
local VIDEO = {   -- container: ffmpeg's format name, then the codec arguments
  mp4 = {"mp4", "-vf pad=ceil(iw/2)*2:ceil(ih/2)*2 -c:v libx264 -pix_fmt yuv420p " ..
                "-crf 18 -movflags +faststart"},
  mkv = {"matroska", "-vf pad=ceil(iw/2)*2:ceil(ih/2)*2 -c:v libx264 -pix_fmt yuv420p -crf 18"},
  mov = {"mov", "-vf pad=ceil(iw/2)*2:ceil(ih/2)*2 -c:v libx264 -pix_fmt yuv420p -crf 18"},
  webm = {"webm", "-c:v libvpx-vp9 -pix_fmt yuv420p -crf 30 -b:v 0"},
  gif = {"gif", "-vf split[a][b];[a]palettegen=stats_mode=diff[p];" ..
                "[b][p]paletteuse=dither=bayer:bayer_scale=5 -loop 0"},
}

local function quote(s) return "'" .. s:gsub("'", [['\'']]) .. "'" end

local function log(fmt, ...)
  io.stderr:write(fmt:format(...), "\n")
  io.stderr:flush()
end

local function exists(path)
  local f = io.open(path, "rb")
  if not f then return false end
  local size = f:seek("end")
  f:close()
  return size and size > 0          -- renames are atomic: a file is whole
end

-- An error object that prints as its message alone: the lancer command and
-- lua5.4 print no traceback for it (their message handlers use __tostring).
local failure_mt = {__tostring = function(e) return e.msg end}
local function fail(msg) error(setmetatable({msg = msg}, failure_mt), 0) end

local function usage(msg) M.usage(msg) end

-- Reads an output pattern: printf style ("out/f_%04d.png", "%%" for a
-- literal %) or Blender style ("out/f_####.png", one run of #). Returns a
-- function from frame number to path and the pattern as ffmpeg's image2
-- reader wants it; or nil and why not.
function M.pattern(p)
  if type(p) ~= "string" then
    return nil, ("string expected, got %s"):format(type(p))
  end
  local fields, bad = 0, false
  local rest = p:gsub("%%%%", "")
  for digits, conv in rest:gmatch("%%(%d*)(.?)") do  -- %d and %0Nd, as ffmpeg reads
    if conv == "d" and (digits == "" or digits:match("^0%d+$")) then
      fields = fields + 1
    else
      bad = true
    end
  end
  local runs = select(2, p:gsub("#+", ""))
  if fields == 1 and not bad and runs == 0 then
    return function(n) return p:format(n) end, p
  elseif fields == 0 and runs == 1 then
    local pre, hashes, post = p:match("^(.-)(#+)(.*)$")
    local num = "%0" .. #hashes .. "d"
    return function(n) return pre .. num:format(n) .. post end,
           pre:gsub("%%", "%%%%") .. num .. post:gsub("%%", "%%%%")
  elseif fields + runs == 0 then
    return nil, ("needs a frame field such as %%04d or ####, got '%s'"):format(p)
  else
    return nil, ("needs exactly one frame field (%%04d, %%d or a run of #), got '%s'"):format(p)
  end
end

local function argerror(field, fmt, ...)
  error(("bad argument #1 to 'animate' (field '%s': %s)"):format(field, fmt:format(...)), 0)
end

local function check_integer(spec, field, min, default)
  local v = spec[field]
  if v == nil then
    if default == nil then argerror(field, "required, got nil") end
    return default
  end
  if math.type(v) ~= "integer" and not (type(v) == "number" and v == math.floor(v)) then
    argerror(field, "integer expected, got %s", type(v) == "number" and tostring(v) or type(v))
  end
  v = math.tointeger(v)
  if not v or v < min or v > 1e9 then
    argerror(field, "must be in [%d, 1000000000], got %s", min, tostring(spec[field]))
  end
  return v
end

local function check(spec)
  if type(spec) ~= "table" then
    error(("bad argument #1 to 'animate' (table expected, got %s)"):format(type(spec)), 0)
  end
  local known = {}
  for _, k in ipairs(FIELDS) do known[k] = true end
  for k in pairs(spec) do
    if not known[k] then
      error(("bad argument #1 to 'animate' (unknown field '%s'; fields are %s)"):format(
        tostring(k), table.concat(FIELDS, ", ")), 0)
    end
  end
  local a = {}
  a.count = check_integer(spec, "frames", 1)
  a.first = check_integer(spec, "first", 0, 1)
  a.last = a.first + a.count - 1
  a.fps = spec.fps == nil and 24 or spec.fps
  if type(a.fps) ~= "number" or not (a.fps > 0 and a.fps < math.huge) then
    argerror("fps", "positive number expected, got %s", tostring(spec.fps))
  end
  a.loop = spec.loop
  if a.loop ~= nil and type(a.loop) ~= "boolean" then
    argerror("loop", "boolean expected, got %s", type(a.loop))
  end
  if type(spec.frame) ~= "function" then
    argerror("frame", "function expected, got %s", type(spec.frame))
  end
  a.frame = spec.frame
  a.render = spec.render or {}
  if type(a.render) ~= "table" then
    argerror("render", "table expected, got %s", type(a.render))
  end
  if a.render.frame ~= nil then
    argerror("render", "'frame' is set by animate to each frame's number")
  end
  a.output = spec.output
  local over = M.options
  local path, ffpat = M.pattern(over.output or a.output)
  if not path then
    if over.output then usage("option '-o' " .. ffpat) end
    argerror("output", "%s", ffpat)
  end
  a.path, a.ffmpeg_pattern = path, ffpat
  return a
end

-- The frame numbers to render, ascending, each once: the command line's
-- --frames ranges (over.frames) or the whole animation,
-- then only those n with n % N == K under --shard K/N.
function M.select(a, over)
  local chosen = {}
  if over.frames then
    for _, r in ipairs(over.frames) do
      local lo, hi, step = r[1], r[2], r[3] or 1
      if lo < a.first or hi > a.last then
        local which = lo == hi and ("frame " .. lo) or ("%d-%d"):format(lo, hi)
        usage(("option '%s': %s is outside the animation's frames %d-%d"):format(
          r.option or "--frames", which, a.first, a.last))
      end
      for n = lo, hi, step do chosen[n] = true end
    end
  else
    for n = a.first, a.last do chosen[n] = true end
  end
  local list = {}
  for n in pairs(chosen) do
    if not over.shard or n % over.shard[2] == over.shard[1] then list[#list + 1] = n end
  end
  table.sort(list)
  return list
end

-- What the frame function receives.
local function frame_info(a, n)
  local i = n - a.first
  local clock = 0
  if a.loop then clock = i / a.count elseif a.count > 1 then clock = i / (a.count - 1) end
  return {number = n, index = i, clock = clock, time = i / a.fps, fps = a.fps,
          first = a.first, last = a.last, frames = a.count, output = a.path(n)}
end

local function ensure_dir(path)
  local dir = path:match("^(.*)/[^/]*$")
  if dir and dir ~= "" and not os.rename(dir, dir) then
    os.execute("mkdir -p " .. quote(dir) .. " 2>/dev/null")
  end
end

local function total_rays(st)
  local n = 0
  for k, v in pairs(st.rays) do
    if k ~= "cut" then n = n + v end
  end
  return n
end

local function render_frame(a, f)
  math.randomseed(f.number, M.seed or 0)   -- (n, 0) is what randomseed(n) sets
  local scene, opts = a.frame(f)
  if getmetatable(scene) == nil or not tostring(scene):match("^lancer%.Scene") then
    error(("the frame function must return a lancer.Scene, got %s"):format(
      scene == nil and "nil" or tostring(scene)), 0)
  end
  if opts ~= nil and type(opts) ~= "table" then
    error(("the frame function's second result must be a table of render " ..
           "options, got %s"):format(type(opts)), 0)
  end
  local o = {}
  for k, v in pairs(a.render) do o[k] = v end
  for k, v in pairs(opts or {}) do o[k] = v end
  o.frame = f.number
  local img, st = scene:render(o)
  ensure_dir(f.output)
  img:save(f.output)
  return img, st
end

-- Frees a frame's image once it is saved and logged: nothing else holds
-- it, and its pixels (25 MB at 1080p) need not wait for the collector.
local function free(img)
  local mt = getmetatable(img)
  if type(mt) == "table" and mt.__close then mt.__close(img) end
end

local function is_interrupt(msg)
  msg = tostring(msg)
  return msg:find("interrupted!", 1, true) or msg:find("render cancelled", 1, true)
end

-- The ffmpeg command that turns the animation's frames into `video`.
function M.ffmpeg_command(a, video, out)
  local ext = video:match("%.(%w+)$")
  local v = VIDEO[ext and ext:lower() or ""]
  local args = v[2]:gsub("(-vf )(%S+)", function(flag, graph) return flag .. quote(graph) end)
  return ("ffmpeg -nostdin -y -loglevel error -framerate %s -start_number %d -i %s " ..
          "-frames:v %d %s -f %s %s"):format(tostring(a.fps), a.first, quote(a.ffmpeg_pattern),
          a.count, args, v[1], quote(out or video))
end

local function have_ffmpeg()
  return os.execute("command -v ffmpeg >/dev/null 2>&1") == true
end

-- Every frame of the animation must be there: ffmpeg stops silently at
-- the first gap and still exits 0.
local function assemble(a, video)
  local missing = {}
  for n = a.first, a.last do
    if not exists(a.path(n)) then missing[#missing + 1] = a.path(n) end
  end
  if #missing > 0 then
    fail(("video: %d of %d frames missing, not assembling %s (first missing: %s)"):format(
      #missing, a.count, video, missing[1]))
  end
  ensure_dir(video)
  local tmp = video .. ".tmp"
  local ok = os.execute(M.ffmpeg_command(a, video, tmp))
  if not ok or not os.rename(tmp, video) then
    os.remove(tmp)
    fail(("video: ffmpeg failed to write %s"):format(video))
  end
  log("video: %s, %d frames at %s fps", video, a.count, tostring(a.fps))
end

-- lancer.animate{frames = N, fps = 24, first = 1, output = "out/f_%04d.png",
--                render = {...}, loop = false, frame = function(f) ... end}
-- Returns {rendered = n, skipped = n, failed = {frame numbers}}; raises
-- after trying every frame when any failed.
function M.animate(spec)
  local checked, a = pcall(check, spec)
  if not checked then error(a, 2) end     -- at the caller's line
  local over = M.options
  M.count = M.count + 1
  local frames = M.select(a, over)
  if over.list_frames then
    for _, n in ipairs(frames) do
      local p = target(a.path(n))
      if not (over.skip_existing and exists(p)) then io.write(p, "\n") end
    end
    io.flush()
    return {rendered = 0, skipped = 0, failed = {}}
  end
  if over.video and not have_ffmpeg() then
    fail(("video: ffmpeg is not installed (Debian: apt-get install ffmpeg); render " ..
          "without --video, then assemble the frames with:\n  %s"):format(
          M.ffmpeg_command(a, over.video)))
  end
  local result = {rendered = 0, skipped = 0, failed = {}}
  M.busy = true
  for _, n in ipairs(frames) do
    local f = frame_info(a, n)
    if over.skip_existing and exists(target(f.output)) then
      result.skipped = result.skipped + 1
      log("frame %d: skipped, %s exists", n, target(f.output))
    else
      -- pcall, not xpcall: a Lua message handler is where a Ctrl-C pending
      -- from a cancelled render would strike, and hide "render cancelled".
      local ok, img, st = pcall(render_frame, a, f)
      if ok then
        result.rendered = result.rendered + 1
        log("frame %d: %dx%d, %d spp, %.3f s, %d rays -> %s", n, img.width, img.height,
            st.rays.camera // (img.width * img.height), st.seconds + (st.lua_seconds or 0),
            total_rays(st), target(f.output))
        free(img)
      elseif is_interrupt(img) then
        M.busy = false
        error(img, 0)
      else
        result.failed[#result.failed + 1] = n
        log("frame %d: FAILED: %s", n, tostring(img))
      end
    end
  end
  M.busy = false
  if #result.failed > 0 then
    fail(("animate: %d of %d frames failed (%s)"):format(#result.failed, #frames,
         table.concat(result.failed, ", ")))
  end
  if over.video then assemble(a, over.video) end
  return result
end

return M
