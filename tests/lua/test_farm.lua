-- test_farm.lua: an animation split across GNU parallel workers gives the
-- same files, byte for byte, as one process rendering every frame.
-- GNU parallel is a test dependency (tools/install-deps.sh test installs
-- it), so its absence is a failure, not a skip.
local T = require "harness"

local q = T.quote
local L = q(T.lancer)

local temp_dir = T.temp_dir

-- 12 frames, jittered samples, math.random in the frame function, and a
-- frame that fails when FAIL names it.
local ANIM = [[
local lancer = require "lancer"
lancer.animate{
  frames = 12, fps = 12, output = arg[1],
  render = {width = 32, height = 24, samples = 4},
  frame = function(f)
    if f.number == tonumber(os.getenv("FAIL") or -1) then error("broken frame") end
    local s = lancer.scene{camera = lancer.camera{from = {0, 1.5, -5}, at = {0, 0, 0}},
                           max_depth = 2}
    local a = 2 * math.pi * f.clock
    s:add(lancer.plane{point = {0, -1, 0}, normal = {0, 1, 0},
                       material = lancer.material{kd = 0.6, kr = 0.4}})
    s:add(lancer.sphere{center = {math.cos(a), 0, math.sin(a)}, radius = 1,
                        material = lancer.material{color = {0.9, 0.3, 0.2}, ks = 0.5}})
    s:add(lancer.point_light{position = {2 + math.random(), 4, -3}, intensity = 25})
    return s
  end}
]]

local function frames(dir, prefix)
  local t = {}
  for n = 1, 12 do
    t[n] = T.slurp(("%s/%s_%04d.png"):format(dir, prefix, n))
    assert(t[n] and t[n]:sub(2, 4) == "PNG", ("%s_%04d.png missing"):format(prefix, n))
  end
  return t
end

T.test("GNU parallel, 2 workers: 12 frames byte-identical to one process", function()
  if os.execute("command -v parallel >/dev/null 2>&1") ~= true then
    error("GNU parallel is not installed: run tools/install-deps.sh test")
  end
  local dir = temp_dir()
  local script = dir .. "/anim.lua"
  local f = assert(io.open(script, "w"))
  f:write(ANIM)
  f:close()
  local env = "HOME=" .. q(dir) .. " "            -- parallel keeps state in ~/.parallel
  local out, err, code = T.run(("%s %s %s"):format(L, q(script), q(dir .. "/one_%04d.png")))
  assert(code == 0, "single process: " .. err)
  -- One job per frame, as the README's recipe ...
  out, err, code = T.run(("seq 1 12 | %s parallel --will-cite -j2 --joblog %s %s --frame {} %s %s")
    :format(env, q(dir .. "/jobs.log"), L, q(script), q(dir .. "/par_%04d.png")))
  assert(code == 0, ("parallel exited %d: %s"):format(code, err))
  -- ... and one job per shard.
  out, err, code = T.run(("%s parallel --will-cite -j2 %s --shard {}/2 %s %s ::: 0 1")
    :format(env, L, q(script), q(dir .. "/shard_%04d.png")))
  assert(code == 0, ("parallel (shards) exited %d: %s"):format(code, err))
  local one, par, shard = frames(dir, "one"), frames(dir, "par"), frames(dir, "shard")
  for n = 1, 12 do
    assert(par[n] == one[n], ("frame %d differs under parallel --frame"):format(n))
    assert(shard[n] == one[n], ("frame %d differs under parallel --shard"):format(n))
  end
  assert(one[1] ~= one[2], "frames 1 and 2 are alike: the test proves nothing")
  local log = T.slurp(dir .. "/jobs.log")
  T.eq(select(2, log:gsub("\n", "")), 13, "job log lines (header and 12 jobs)")
  -- A failing frame fails its job: parallel's exit status counts them.
  out, err, code = T.run(("seq 1 12 | FAIL=7 %s parallel --will-cite -j2 %s --frame {} %s %s")
    :format(env, L, q(script), q(dir .. "/bad_%04d.png")))
  T.eq(code, 1, "parallel's exit status with one frame failing")
  assert(err:find("frame 7: FAILED: " .. script .. ":6: broken frame", 1, true), err)
  os.execute("rm -rf " .. q(dir))
end)
