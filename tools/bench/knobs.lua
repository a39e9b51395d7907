-- knobs.lua: docs/numerics.md T5, the cost of each sampling knob is linear:
-- trace time at 256 over trace time at 16 within [14.4, 17.6] for camera
-- samples per pixel, cone samples per glossy hit and light samples per
-- area light, each with the other two at 1.
--
-- Rendered in this process (bench.lua runs under lancer), on one scene
-- built here so that every knob has work to do: a glossy floor filling
-- most of the frame (cone rays at every floor pixel), diffuse shapes it
-- reflects, and one emissive quad above as the only light (light samples
-- at every diffuse hit; cut into 8 for the light_samples knob). Levels alternate (16, 256, 16, 256, ...) so a
-- noisy spell on the shared machine hits both; the ratio is the median of
-- the fastest run's at 256 over the fastest run's at 16: on a shared
-- machine the other work only ever adds time, so the least time of each
-- is the nearest its cost (ratios of single runs of the same pair spread
-- from 13.4 to 16.6). Each run times 16 renders at 16 back to back against
-- one at 256, so both sides last as long.
local lancer = require "lancer"

local M = {}

M.LOW, M.HIGH = 16, 256
M.REPEAT = {[16] = 16, [256] = 1}   -- renders per timing: about equal durations
M.BAND = {14.4, 17.6}       -- 16x within 10 %
M.KNOBS = {"samples", "cone_samples", "light_samples"}
-- Image sides: a camera sample costs several rays, a cone sample one, so
-- it gets 2x the pixels (light samples, 8 emitters' worth, need none); at 16
-- each render then takes 0.1-0.3 s
-- on one thread, long enough for the clock, short enough for make bench.
-- Smaller images in quick mode measured ratios off by 20 % (0.04 s renders).
M.SIDE = {samples = 128, cone_samples = 192, light_samples = 128}

function M.scene(knob)
  local s = lancer.scene{
    camera = lancer.camera{from = {0, 2.2, -5}, at = {0, 0.3, 0}, fov = 60},
    background = {0.05, 0.05, 0.08}, max_depth = 2}
  -- For the cone_samples knob the floor is a pure glossy reflector (kd 0):
  -- its own light sample and shading are cost every pixel pays whatever
  -- the cone count, and with them the fixed part was 13 % at 16 (ratio
  -- 14.1); without, the pixel's cost is its cone rays.
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                     material = lancer.material{color = {0.8, 0.8, 0.75},
                                                kd = knob == "cone_samples" and 0 or 0.5,
                                                kr = 0.5, glossiness = 8}})
  s:add(lancer.sphere{center = {-1, 0.7, 0.5}, radius = 0.7,
                      material = lancer.material{color = {0.85, 0.2, 0.15}}})
  s:add(lancer.box{min = {0.4, 0, -0.3}, max = {1.4, 1, 0.7},
                   material = lancer.material{color = {0.2, 0.4, 0.85}}})
  s:add(lancer.sphere{center = {1.6, 0.35, -1.2}, radius = 0.35})
  -- The only light: a 2x2 emitter 3 above the floor, sampled as an area
  -- light; for the light_samples knob cut into 8 pieces, so that light
  -- samples (S per emitter per hit) outweigh the camera and cone rays every
  -- pixel pays anyway: with one emitter that fixed part was 21 % of the
  -- time at S = 16 and the ratio 12.9. (The other knobs keep one: more
  -- light rays at every camera hit are fixed cost for them.)
  local n = knob == "light_samples" and 4 or 1
  for i = 0, n - 1 do
    for k = 0, (n > 1 and 1 or 0) do
      s:add(lancer.quad{corner = {-1 + 2 * i / n, 3, -1 + k}, u = {2 / n, 0, 0},
                        v = {0, 0, n > 1 and 1 or 2},
                        material = lancer.material{kd = 0, emission = 6}})
    end
  end
  return s
end

-- ctx: {say, quick, runs}; quick: two runs (about 30 s), else 5 (about 75 s).
-- Returns the Markdown section.
function M.section(ctx)
  local say = ctx.say
  local runs = ctx.runs or (ctx.quick and 2 or 5)
  local rows = {}
  for _, knob in ipairs(M.KNOBS) do
    local scene = M.scene(knob)
    local side = M.SIDE[knob]
    -- One thread: the cost of a sample, without tile scheduling or the
    -- other core's load in it.
    local base = {width = side, height = side, samples = 1, cone_samples = 1,
                  light_samples = 1, threads = 1, progress = false}
    -- CPU seconds of this process around the render (one tracing thread, so
    -- the render's own work) and the trace's wall seconds. The gate is on
    -- CPU time: with 4 people on 2 cores, wall ratios of the same pair
    -- ranged from 10 to 20 while the work did not change.
    local cpu, wall, ratios, wall_ratios, rays = {[M.LOW] = {}, [M.HIGH] = {}},
      {[M.LOW] = {}, [M.HIGH] = {}}, {}, {}, {}
    for i = 1, runs do
      for _, level in ipairs{M.LOW, M.HIGH} do
        local o = {}
        for k, v in pairs(base) do o[k] = v end
        o[knob] = level
        local reps = M.REPEAT[level]
        local c0, w, st = os.clock(), 0, nil
        for _ = 1, reps do
          _, st = scene:render(o)
          w = w + st.trace_seconds
        end
        cpu[level][i] = (os.clock() - c0) / reps
        wall[level][i] = w / reps
        rays[level] = st.rays
      end
      ratios[i] = cpu[M.HIGH][i] / cpu[M.LOW][i]
      wall_ratios[i] = wall[M.HIGH][i] / wall[M.LOW][i]
      say("  %-13s run %d: %d -> %.3f s, %d -> %.3f s CPU, ratio %.2f (wall %.2f)", knob,
          i, M.LOW, cpu[M.LOW][i], M.HIGH, cpu[M.HIGH][i], ratios[i], wall_ratios[i])
    end
    local function median(list)
      table.sort(list)
      return list[(#list + 1) // 2]
    end
    local function least(list)
      local m = math.huge
      for _, x in ipairs(list) do m = math.min(m, x) end
      return m
    end
    local low, high = least(cpu[M.LOW]), least(cpu[M.HIGH])
    -- The rays of the knob's own kind must grow 16x exactly or the timing
    -- measures something else.
    local kind = ({samples = "camera", cone_samples = "glossy",
                   light_samples = "light"})[knob]
    rows[#rows + 1] = {knob = knob, side = side, low = low, high = high,
                       ratio = high / low, median_ratio = median(ratios),
                       wall_ratio = median(wall_ratios),
                       kind = kind, rays_low = rays[M.LOW][kind] or 0,
                       rays_high = rays[M.HIGH][kind] or 0}
  end

  local lines = {"## Cost linear in each knob (T5)\n\n",
    ("CPU seconds of one-thread renders (the least of %d run%s, each timing 16\n"):format(
      runs, runs == 1 and "" or "s"),
    "renders at 16 against one at 256, so both last as long) of the scene in\n",
    "`tools/bench/knobs.lua` (glossy floor, diffuse shapes, one emissive quad as the\n",
    "only light, cut into 8 for light_samples), each knob at 16 and 256 with the other two at 1. The ratio is the\n",
    "least time at 256 over the least at 16 (other work on a shared machine only adds\n",
    "time); beside it, the median of the runs' own ratios and of their wall-clock trace\n",
    "ratios, which swing with the machine's load. Target: the ratio in [14.4, 17.6], 16x within 10 %.\n",
    "With time = a + b x level (a: the camera ray and shading every pixel costs\n",
    "anyway) the ratio is (a + 256b) / (a + 16b); the last column is a's share of\n",
    "the time at 16, from the two least times (negative: noise).\n\n",
    "| knob | image | rays of its kind, 16 -> 256 | CPU at 16 (s) |",
    " CPU at 256 (s) | ratio | runs' median (wall) | target | fixed share at 16 |\n",
    "| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n"}
  for _, r in ipairs(rows) do
    local ok = r.ratio >= M.BAND[1] and r.ratio <= M.BAND[2]
    local b = (r.high - r.low) / (M.HIGH - M.LOW)
    local fixed = (r.low - M.LOW * b) / r.low
    lines[#lines + 1] = ("| %s | %dx%d | %s %d -> %d (%.2fx) | %.3f | %.3f | %.2f | %.2f (%.2f) " ..
                         "| %s | %.0f %% |\n")
      :format(r.knob, r.side, r.side, r.kind, r.rays_low, r.rays_high,
      r.rays_low > 0 and r.rays_high / r.rays_low or 0, r.low, r.high, r.ratio,
      r.median_ratio, r.wall_ratio,
      r.rays_low == 0 and "no " .. r.kind .. " rays: knob inactive" or
      ok and "PASS" or "MISS", 100 * fixed)
  end
  return table.concat(lines) .. "\n"
end

return M
