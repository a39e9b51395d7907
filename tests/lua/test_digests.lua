-- test_digests.lua: every scene, example and benchmark script renders the
-- same image bits as when its digest was pinned (tests/lua/digests.lua):
-- code that moves or is restructured must not change a single pixel. Each
-- script is rendered at 48x36 with 1 sample and at 32x24 with 4 samples.
-- A deliberate change of the images rewrites the file with
--   LANCER_PIN_DIGESTS=1 make check
-- and its commit says why the pictures changed.
local T = require "harness"

local PINNED = "tests/lua/digests.lua"
local SIZES = {{width = 48, height = 36, samples = 1}, {width = 32, height = 24, samples = 4}}

-- Script, its arguments (arg[1], ...) and, for animations, frames to render.
local function scripts()
  local list = {}
  local p = assert(io.popen("ls scenes/seed/*.lua scenes/*.lua examples/*.lua"))
  for path in p:lines() do list[#list + 1] = {path} end
  p:close()
  list[#list + 1] = {"scenes/bench/b1.lua", {"1"}}
  list[#list + 1] = {"scenes/bench/b2.lua", {"300"}}
  list[#list + 1] = {"scenes/bench/b3.lua", {"24"}}
  list[#list + 1] = {"scenes/bench/s7.lua", {"-", "32", "1", "1"}}
  list[#list + 1] = {"scenes/bench/glass.lua", {"1"}}
  return list
end

local function load_pinned()
  local chunk = loadfile(PINNED)
  return chunk and chunk() or {}
end

-- The digests of every render the script makes at one size.
local function digests(entry, size)
  local script, args = entry[1], entry[2]
  local tmp = os.tmpname()
  os.remove(tmp)
  local frames, out = nil, tmp .. ".png"
  local text = T.slurp(script)
  if script:match("05_frames%.lua$") then
    out = tmp
  elseif text:find("lancer.animate", 1, true) then
    out, frames = tmp .. "_%04d.png", {{1, 2, 1}}
  end
  local argv = args and {[0] = script, table.unpack(args)} or {[0] = script, out}
  local got = {}
  T.run_script(script, argv, frames, size, function(img)
    got[#got + 1] = T.image_digest(img)
  end)
  os.execute(("rm -rf %s %s*"):format(T.quote(tmp), T.quote(tmp)))
  return table.concat(got, " ")
end

local function key(entry, size)
  return ("%s%s @%dx%dx%d"):format(entry[1], entry[2] and " " .. table.concat(entry[2], " ")
                                   or "", size.width, size.height, size.samples)
end

local pin = os.getenv("LANCER_PIN_DIGESTS") == "1"
local pinned, fresh = load_pinned(), {}

for _, entry in ipairs(scripts()) do
  for _, size in ipairs(SIZES) do
    local k = key(entry, size)
    T.test("digest " .. k, function()
      local d = digests(entry, size)
      fresh[k] = d
      if pin then return end
      assert(pinned[k], ("no pinned digest for %s (got %s): pin with LANCER_PIN_DIGESTS=1")
             :format(k, d))
      T.eq(d, pinned[k], k .. " image digests")
    end)
  end
end

if pin then
  T.test("digests pinned into " .. PINNED, function()
    local keys = {}
    for k in pairs(fresh) do keys[#keys + 1] = k end
    table.sort(keys)
    local f = assert(io.open(PINNED, "w"))
    f:write("-- digests.lua: pinned image digests (tests/lua/test_digests.lua).\nreturn {\n")
    for _, k in ipairs(keys) do f:write(("  [%q] = %q,\n"):format(k, fresh[k])) end
    f:write("}\n")
    f:close()
  end)
end
