-- test_memory.lua: images, meshes and scenes hold memory Lua's collector
-- cannot see (a userdata of 8 bytes); the binding tells it, so discarded
-- renders do not pile up, and lancer.animate frees each frame it saved.
local T = require "harness"
local lancer = require "lancer"

-- Runs a script with the lancer command (a generational collector, as
-- the command sets) and returns its peak resident memory in bytes, which
-- the script prints last as "peak <kB>". ASan's quarantine would keep
-- what is freed: it is turned off for these runs.
local function peak_of(script, ...)
  local dir = T.temp_dir()
  local path = dir .. "/script.lua"
  T.write(path, script .. [[

for line in io.lines("/proc/self/status") do
  local kb = line:match("^VmHWM:%s*(%d+) kB")
  if kb then print("peak " .. kb) end
end
]])
  local args = {}
  for i, a in ipairs{...} do args[i] = T.quote(tostring(a)) end
  local asan = os.getenv("ASAN_OPTIONS") or "detect_leaks=0"
  local env = "ASAN_OPTIONS=" .. T.quote(asan .. ":quarantine_size_mb=0")
  local out, err, code = T.run(("%s %s %s %s"):format(env, T.quote(T.lancer),
                               T.quote(path), table.concat(args, " ")))
  os.execute("rm -rf " .. T.quote(dir))
  T.check_exit(code, 0, out, err)
  local kb = assert(out:match("peak (%d+)"), "no peak printed: " .. out)
  return tonumber(kb) * 1024
end

local MB = 1024 * 1024

T.test("24 discarded 1000x1000 renders peak within 3 images of one", function()
  local script = [[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}},
                       background = {0.2, 0.3, 0.4}, ambient = 0.1}
for i = 1, tonumber(arg[1]) do
  local img = s:render{width = 1000, height = 1000, samples = 1, progress = false}
end]]
  local image = 1000 * 1000 * 3 * 4
  local one, many = peak_of(script, 1), peak_of(script, 24)
  -- Before: 24 images (288 MB) on top of one; now at most one or two more.
  assert(many - one < 3 * image, ("24 renders peak %.1f MB, one %.1f MB"):format(
    many / MB, one / MB))
end)

T.test("a 24-frame animation peaks within 3 frames of a 1-frame one", function()
  local script = [[
local lancer = require "lancer"
local out = os.tmpname()
os.remove(out)
os.execute("mkdir -p " .. out)
lancer.animate{frames = tonumber(arg[1]), output = out .. "/f_%04d.png",
  render = {width = 800, height = 600, samples = 1},
  frame = function(f)
    local s = lancer.scene{camera = lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}},
                           ambient = 0.1}
    s:add(lancer.sphere{center = {f.clock, 0, 0}, radius = 1})
    return s
  end}
os.execute("rm -rf " .. out)]]
  local frame = 800 * 600 * 3 * 4
  local one, many = peak_of(script, 1), peak_of(script, 24)
  assert(many - one < 3 * frame, ("24 frames peak %.1f MB, one %.1f MB"):format(
    many / MB, one / MB))
end)

T.test("lancer.animate frees each frame's image once it is saved", function()
  local dir = T.temp_dir()
  local seen = {}
  local old = lancer.set_host_hook(function(method, plain, ...)
    local img, st = plain(...)
    if method == "render" then seen[#seen + 1] = img end
    return img, st
  end)
  local saved_stderr = io.stderr
  io.stderr = {write = function() end, flush = function() end}   -- frame logs
  local ok, err = pcall(lancer.animate, {frames = 3, output = dir .. "/f_%04d.png",
    render = {width = 8, height = 6},
    frame = function()
      local s = lancer.scene{camera = lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}},
                             ambient = 0.1}
      s:add(lancer.sphere{center = {0, 0, 0}, radius = 1})
      return s
    end})
  io.stderr = saved_stderr
  lancer.set_host_hook(old)
  os.execute("rm -rf " .. T.quote(dir))
  assert(ok, err)
  T.eq(#seen, 3, "frames rendered")
  for i, img in ipairs(seen) do
    T.eq(tostring(img), "lancer.Image (freed)", "frame " .. i)
  end
end)
