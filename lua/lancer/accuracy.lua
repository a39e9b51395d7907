-- lancer.accuracy: `lancer --accuracy SCRIPT.lua --knob samples=1,4,16,64`.
-- Each render the script asks for is done at every level of each knob, with
-- several seeds, and measured against a reference rendered with 16 times
-- the largest level (docs/numerics.md 3.1): a table of error, time and
-- efficiency on stdout, a CSV and a log-log plot of error against time.
--
-- The reference is two renders with seeds of their own, each with half its
-- budget, averaged: their difference gives the reference's own variance
-- (MSE(a, b) / 4 for the average) for free, which must stay well under the
-- smallest error it measures. Errors are on linear radiance (img:error).
local M = {renders = 0}

local REF_FACTOR = 16          -- the reference's budget over the largest level
local DEPTH_REF = 64           -- docs/numerics.md 3.1's reference depth
local REF_SEED = 1000001       -- the reference's two seeds; levels use 1..seeds
local SIDE = 160               -- longest side by default: keeps the reference affordable
local DEFAULT_SEEDS = 4

-- The knobs: the render option each sets, the smallest level the option
-- takes, the most the core allows (lancer.h), and how the reference is made.
local KNOBS = {
  samples       = {min = 1, max = 1 << 20, ref = "budget"},
  cone_samples  = {min = 1, max = 4096, ref = "budget"},
  light_samples = {min = 0, max = 4096, ref = "budget"},
  max_depth     = {min = 0, max = 1000000, ref = "depth"},
  indirect      = {min = 0, max = 1024, ref = "bounces"},
  -- Adaptive sampling's target: a number in (0, 1], levels decreasing
  -- (each asks for less noise); the reference is uniform sampling.
  noise         = {min = 0, max = 1, ref = "uniform", real = true},
}
local ORDER = {"samples", "cone_samples", "light_samples", "max_depth", "indirect", "noise"}
local ALIASES = {depth = "max_depth"}
-- Ray kinds in a fixed column order; any other kind the core reports is
-- appended in name order.
local KINDS = {"camera", "shadow", "reflection", "refraction", "glossy", "light", "indirect",
               "ao", "cut"}

local function say(fmt, ...) io.stderr:write("accuracy: ", fmt:format(...), "\n") end

-- Parses "NAME=L1,L2,..."; returns {name, levels} or nil and the usage error.
local function parse_knob(spec)
  local name, list = spec:match("^([%w_]+)=(.*)$")
  if not name then
    return nil, ("option '--knob' needs NAME=L1,L2,..., got '%s'"):format(spec)
  end
  name = ALIASES[name] or name
  local k = KNOBS[name]
  if not k then
    return nil, ("option '--knob': unknown knob '%s'; knobs are %s (or depth)"):format(
      name, table.concat(ORDER, ", "))
  end
  if list == "" then
    return nil, ("option '--knob': no levels for %s"):format(name)
  end
  local levels = {}
  for item in (list .. ","):gmatch("([^,]*),") do
    local v = tonumber(item)
    if k.real then
      if not v or v ~= v then
        return nil, ("option '--knob': %s level '%s' is not a number"):format(name, item)
      end
      if v <= k.min or v > k.max then
        return nil, ("option '--knob': %s levels must be in (%g, %g], got %s"):format(
          name, k.min, k.max, item)
      end
      if #levels > 0 and v >= levels[#levels] then
        return nil, ("option '--knob': %s levels must decrease, got %s after %g"):format(
          name, item, levels[#levels])
      end
    else
      v = math.tointeger(v)
      if not v then
        return nil, ("option '--knob': %s level '%s' is not an integer"):format(name, item)
      end
      if v < k.min or v > k.max then
        return nil, ("option '--knob': %s levels must be in [%d, %d], got %d"):format(
          name, k.min, k.max, v)
      end
      if #levels > 0 and v <= levels[#levels] then
        return nil, ("option '--knob': %s levels must increase, got %d after %d"):format(
          name, v, levels[#levels])
      end
    end
    levels[#levels + 1] = v
  end
  return {name = name, levels = levels}
end

-- Called by the lancer command before the script runs: {knobs = {specs},
-- seeds, out, script}. Returns true, or nil and a one-line usage error.
function M.setup(t)
  local knobs = {}
  for _, spec in ipairs(t.knobs or {}) do
    local k, why = parse_knob(spec)
    if not k then return nil, why end
    knobs[#knobs + 1] = k
  end
  if #knobs == 0 then return nil, "option '--accuracy' needs --knob NAME=L1,L2,..." end
  local seeds = t.seeds or DEFAULT_SEEDS
  if math.type(seeds) ~= "integer" or seeds < 2 then
    return nil, ("option '--seeds' needs an integer >= 2, got %s"):format(tostring(seeds))
  end
  local script = (t.script or "stdin"):match("([^/]*)$"):gsub("%.lua$", "")
  M.config = {knobs = knobs, seeds = seeds, out = t.out or "out/accuracy",
              script = script ~= "" and script or "script"}
  return true
end

-- ---- Measuring ---------------------------------------------------------------

local function copy(t)
  local c = {}
  for k, v in pairs(t) do c[k] = v end
  return c
end

local function median(list)
  local s = copy(list)
  table.sort(s)
  local m = (#s + 1) // 2
  return #s % 2 == 1 and s[m] or (s[m] + s[m + 1]) / 2
end

-- Every ray kind the core reports, in column order.
local function kinds_of(rays)
  local list, seen = {}, {}
  for _, k in ipairs(KINDS) do list[#list + 1] = k; seen[k] = true end
  local extra = {}
  for k in pairs(rays) do if not seen[k] then extra[#extra + 1] = k end end
  table.sort(extra)
  for _, k in ipairs(extra) do list[#list + 1] = k end
  return list
end

-- Rays traced: every kind but "cut" (bounces the cutoff saved, not traced).
local function traced(rays)
  local n = 0
  for k, v in pairs(rays) do if k ~= "cut" then n = n + v end end
  return n
end

-- The knob's value in the render options. max_depth also goes to the scene
-- itself, so it takes effect whether or not the core reads the option.
local function set_knob(scene, o, name, value)
  o[name] = value
  if name == "max_depth" then scene.max_depth = value end
end

-- The reference's knob value and each half's value, with a description;
-- a fourth value, when there is one, is each half's camera samples.
local function reference_plan(knob, samples)
  local k, top = KNOBS[knob.name], knob.levels[#knob.levels]
  if k.ref == "bounces" then
    -- Bounces of light, as depth, but every path is random: the halves
    -- also take 16 / 2 times the camera samples, or the reference's noise
    -- would be the levels' own.
    local d = math.min(k.max, math.max(DEPTH_REF, 4 * top))
    local s = math.max(1, REF_FACTOR * samples // 2)
    return d, d, ("%s=%d, samples=%d, 2 renders of %d averaged"):format(knob.name, d,
      2 * s, s), s
  end
  if k.ref == "uniform" then
    -- Adaptive sampling stops each pixel at `noise` or at `samples`; the
    -- reference takes 4 times that cap in every pixel, in two halves.
    local s = 2 * samples
    return 0, 0, ("noise=0 (uniform), samples=%d, 2 renders of %d averaged"):format(
      2 * s, s), s
  end
  if k.ref == "depth" then
    -- Depth is a truncation, not a sample count: 16x a depth of 10 costs
    -- nothing more once the cutoff stops the chains, and 64 bounces leave
    -- under 0.92^64 = 0.5 % of a 0.92 mirror's light; 4x the largest
    -- covers sweeps that go past 64. Both halves use that depth and differ
    -- in their seeds only.
    local d = math.min(k.max, math.max(DEPTH_REF, 4 * top))
    return d, d, ("%s=%d, 2 seeds averaged"):format(knob.name, d)
  end
  local total = math.min(k.max, REF_FACTOR * top)
  local half = math.max(1, total // 2)
  local note = total < REF_FACTOR * top and
    (" (capped at %d, the most the core takes)"):format(k.max) or ""
  return 2 * half, half, ("%s=%d%s, 2 renders of %d averaged"):format(knob.name,
    2 * half, note, half)
end

-- Renders (through plain: without the host hook) and measures one knob;
-- returns the result table.
local function sweep(plain, scene, base, knob, seeds)
  local lancer = require "lancer"
  local name, levels = knob.name, knob.levels
  if name == "noise" and (base.samples or 1) <= (base.min_samples or 16) then
    error(("accuracy: knob noise needs samples (the most a pixel takes) above " ..
           "min_samples = %d, got %d: give --samples"):format(base.min_samples or 16,
           base.samples or 1), 0)
  end
  local ref_value, half, ref_note, ref_samples = reference_plan(knob, base.samples or 1)
  local t0 = os.time()
  local halves, ref_stats = {}, nil
  for i = 1, 2 do
    local o = copy(base)
    o.seed = REF_SEED + i - 1
    set_knob(scene, o, name, half)
    o.samples = ref_samples or o.samples
    local img, st = plain(scene, o)
    halves[i] = img
    ref_stats = ref_stats or st
  end
  local ref = lancer.image{width = halves[1].width, height = halves[1].height}
  ref:add(halves[1], 0.5):add(halves[2], 0.5)
  -- Var(a) = MSE(a, b) / 2 for independent a and b; the average halves it.
  local ref_var = halves[1]:error(halves[2]).mse / 4
  say("reference %s in %d s", ref_note, os.time() - t0)

  local r = {knob = name, samples = base.samples or 1, ref_note = ref_note,
             ref_value = ref_value, ref_var = ref_var, width = ref.width,
             height = ref.height, seeds = seeds, levels = {}, runs = {}, kinds = nil}
  for _, level in ipairs(levels) do
    local L = {level = level, seconds = {}, rays = {}, rmse = {}, mse = {}, relmse = {},
               mae = {}, bias = {}}
    for seed = 1, seeds do
      local o = copy(base)
      o.seed = seed
      set_knob(scene, o, name, level)
      local img, st = plain(scene, o)
      local e = img:error(ref)
      r.kinds = r.kinds or kinds_of(st.rays)
      local run = {level = level, seed = seed, seconds = st.trace_seconds,
                   rays = traced(st.rays), by_kind = st.rays, e = e}
      r.runs[#r.runs + 1] = run
      for _, k in ipairs{"seconds", "rays"} do L[k][seed] = run[k] end
      for _, k in ipairs{"rmse", "mse", "relmse", "mae", "bias"} do L[k][seed] = e[k] end
    end
    local function mean(list)
      local s = 0
      for _, v in ipairs(list) do s = s + v end
      return s / #list
    end
    L.median_seconds = median(L.seconds)
    L.mean_rays = mean(L.rays)
    L.mean_rmse, L.mean_mse, L.mean_relmse = mean(L.rmse), mean(L.mse), mean(L.relmse)
    L.mean_mae, L.mean_bias = mean(L.mae), mean(L.bias)
    L.min_rmse = math.min(table.unpack(L.rmse))
    L.max_rmse = math.max(table.unpack(L.rmse))
    L.efficiency = 1 / (L.mean_relmse * L.median_seconds)
    r.levels[#r.levels + 1] = L
    say("%s=%g: %d seeds, RMSE %.4g, %.3f s each", name, level, seeds, L.mean_rmse,
        L.median_seconds)
  end
  local best, smallest = r.levels[1], math.huge
  for _, L in ipairs(r.levels) do
    if L.efficiency > best.efficiency then best = L end
    smallest = math.min(smallest, L.mean_mse)
  end
  r.best, r.smallest_mse = best, smallest
  return r, ref, ref_stats
end

-- ---- Reporting ---------------------------------------------------------------

local function num(x) return ("%.6g"):format(x) end

local function table_text(r, label)
  local out = {}
  local function add(fmt, ...) out[#out + 1] = fmt:format(...) end
  add("%s at %dx%d, knob %s, %d seeds per level", label, r.width, r.height, r.knob,
      r.seeds)
  local ratio = r.ref_var == 0 and 0 or r.ref_var / r.smallest_mse   -- inf: 0 MSE
  add("reference: %s; its variance %.3g is %s of the smallest MSE", r.ref_note, r.ref_var,
      ratio == 0 and "0" or ratio < 1 and ("1/%.0f"):format(1 / ratio)
      or ("%.3gx"):format(ratio))
  if ratio > 1 / REF_FACTOR then
    -- The measured MSE is the level's own plus the reference's variance.
    add("warning: the reference is noisier than docs/numerics.md 3.1 allows (1/16): " ..
        "the best level's RMSE is overstated by up to %.0f %%", 100 * (1 - math.sqrt(
        math.max(0, 1 - ratio))))
    if r.knob ~= "samples" and r.samples > 1 then
      add("hint: at samples=%d the pixel noise, which %s does not reduce, is in the " ..
          "reference and in every level; --samples 1 measures %s alone", r.samples,
          r.knob, r.knob)
    end
  end
  add("%14s %9s %12s %10s %21s %10s %11s", r.knob, "seconds", "rays", "RMSE",
      "RMSE min-max", "relMSE", "efficiency")
  for _, L in ipairs(r.levels) do
    add("%14s %9.4f %12.0f %10.4g %10.4g-%-10.4g %10.4g %11.4g", ("%g"):format(L.level),
        L.median_seconds, L.mean_rays, L.mean_rmse, L.min_rmse, L.max_rmse,
        L.mean_relmse, L.efficiency)
  end
  local gain = r.best.efficiency / r.levels[1].efficiency
  local same = true
  for _, L in ipairs(r.levels) do same = same and L.mean_rays == r.levels[1].mean_rays end
  if same and #r.levels > 1 then
    add("note: every level traced the same rays: nothing in this scene uses %s", r.knob)
  end
  add("best value: %s=%g (efficiency %.4g per second%s)", r.knob, r.best.level,
      r.best.efficiency, gain < math.huge and r.best ~= r.levels[1] and
      (", %.2fx %s=%g's"):format(gain, r.knob, r.levels[1].level) or "")
  return table.concat(out, "\n") .. "\n"
end

local function write(path, text)
  local f, why = io.open(path, "w")
  if not f then error("accuracy: cannot write " .. why, 0) end
  f:write(text)
  f:close()
end

local function csv_summary(r)
  local rows = {"knob,level,seeds,seconds,rays,rmse,rmse_min,rmse_max,mse,relmse,mae," ..
                "bias,efficiency"}
  for _, L in ipairs(r.levels) do
    rows[#rows + 1] = table.concat({r.knob, L.level, r.seeds, num(L.median_seconds),
      ("%.0f"):format(L.mean_rays), num(L.mean_rmse), num(L.min_rmse), num(L.max_rmse),
      num(L.mean_mse), num(L.mean_relmse), num(L.mean_mae), num(L.mean_bias),
      num(L.efficiency)}, ",")
  end
  return table.concat(rows, "\n") .. "\n"
end

local function csv_runs(r)
  local head = {"knob", "level", "seed", "seconds", "rays"}
  for _, k in ipairs(r.kinds) do head[#head + 1] = k end
  for _, k in ipairs{"mse", "rmse", "relmse", "mae", "bias"} do head[#head + 1] = k end
  local rows = {table.concat(head, ",")}
  for _, run in ipairs(r.runs) do
    local row = {r.knob, run.level, run.seed, num(run.seconds), run.rays}
    for _, k in ipairs(r.kinds) do row[#row + 1] = run.by_kind[k] or 0 end
    for _, k in ipairs{"mse", "rmse", "relmse", "mae", "bias"} do
      row[#row + 1] = num(run.e[k])
    end
    rows[#rows + 1] = table.concat(row, ",")
  end
  return table.concat(rows, "\n") .. "\n"
end

local function plot(r, path, title)
  local points = {}
  for _, L in ipairs(r.levels) do
    points[#points + 1] = {x = L.median_seconds, y = L.mean_rmse,
                           label = tostring(L.level)}
  end
  return require("lancer.plot").loglog{
    path = path, title = title, xlabel = "trace seconds (median of seeds)",
    ylabel = "RMSE (mean of seeds)", points = points,
    series = r.knob,
    -- RMSE against time: -1/2 is plain Monte Carlo (independent samples, cost
    -- linear in the knob); -1 what stratification reaches on smooth integrands.
    slopes = {{-0.5, "slope -1/2 (independent)"},
              {-1, "slope -1 (stratified)"}}}
end

-- ---- The diverted render ------------------------------------------------------

-- Called by the lancer command's host hook (lancer.host) in place of the
-- render the script asked for; plain renders without the hook, cli holds
-- the command's --width, --height and --samples. Returns the last knob's
-- reference image and its first half's statistics.
function M.render(scene, opts, plain, cli)
  local cfg = assert(M.config, "lancer.accuracy.setup was not called")
  M.renders = M.renders + 1
  local base = copy(opts or {})
  -- --width and --height hold for every render of the sweep; --samples is
  -- the script's own value here: the sweep sets samples itself.
  base.width, base.height = cli.width or base.width, cli.height or base.height
  if cli.samples then base.samples = cli.samples end
  base.progress = false
  if not cli.width and not cli.height then
    local w, h = base.width or 640, base.height or 480
    local k = math.min(1, SIDE / math.max(w, h))
    base.width = math.max(1, math.floor(w * k + 0.5))
    base.height = math.max(1, math.floor(h * k + 0.5))
  end
  local depth = scene.max_depth
  local ok, err = pcall(function()
    assert(os.execute("mkdir -p '" .. cfg.out:gsub("'", [['\'']]) .. "'"),
           "accuracy: cannot create " .. cfg.out)
    local results = {}
    for _, knob in ipairs(cfg.knobs) do
      local name = cfg.script .. (M.renders > 1 and "-" .. M.renders or "") ..
                   "-" .. knob.name
      local prefix = cfg.out .. "/" .. name
      local r, ref, ref_stats = sweep(plain, scene, base, knob, cfg.seeds)
      scene.max_depth = depth
      local label = ("render %d of %s"):format(M.renders, cfg.script)
      io.write(table_text(r, label))
      write(prefix .. ".csv", csv_summary(r))
      write(prefix .. "-runs.csv", csv_runs(r))
      local how = plot(r, prefix .. ".png", ("%s: RMSE against time over %s"):format(
        cfg.script, knob.name))
      io.write(("wrote %s.csv, %s-runs.csv, %s.png (%s)\n\n"):format(prefix, prefix,
               prefix, how))
      io.flush()
      results[#results + 1] = {r = r, ref = ref, stats = ref_stats}
    end
    return results
  end)
  scene.max_depth = depth
  if not ok then error(err, 0) end
  local last = err[#err]
  return last.ref, last.stats
end

-- After the script: false (with a message) when it rendered nothing.
function M.finish()
  if M.renders == 0 then
    say("the script rendered nothing, so there is nothing to measure")
    return false
  end
  return true
end

return M
