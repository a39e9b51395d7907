-- parity.lua: what the full shading costs on a scene that needs none of it
-- (docs/numerics.md S7). scenes/bench/s7.lua (diffuse only, 1024x1024 at 4 spp,
-- 1000 spheres and 1000 triangles, 2 point lights) traced by the normal
-- lancer and by `make MINIMAL=1`'s (src/render/shade_minimal.c: the diffuse path
-- alone, over the same intersection, BVH and camera code), interleaved; the
-- target is at most 1.05x the minimal build's trace time. Both must draw the
-- same image with the same rays.
local lancer = require "lancer"

local M = {}

M.TARGET = 1.05
M.SCRIPT = "scenes/bench/s7.lua"
-- Counters that must agree exactly between the builds (the bench line's keys).
M.COUNTS = {"camera", "shadow", "reflection", "rays", "ptests", "ntests"}

local function fmt(x, f) return x and (f or "%.3f"):format(x) or "-" end

-- The two PNGs, read linear: the largest channel difference (0: identical).
local function png_diff(a_path, b_path)
  local ok, a = pcall(lancer.load_png, a_path, {encoding = "linear"})
  local ok2, b = pcall(lancer.load_png, b_path, {encoding = "linear"})
  if not (ok and ok2) then return nil end
  local ok3, d = pcall(a.diff, a, b, 0)
  return ok3 and d or nil
end

-- Instructions the render loop (render.c's work(), every tile) executes
-- under callgrind, 256x256 at 4 spp on 1 thread: deterministic, where trace
-- times on a shared machine swing by 10 % from run to run. nil without
-- valgrind or on failure.
local function instructions(ctx, which)
  local run = ctx.run
  if not run.available("valgrind") then return nil end
  local data = ("%s/parity-%s.callgrind"):format(ctx.out, which)
  os.execute(("cd %s && valgrind --tool=callgrind --toggle-collect=work " ..
    "--callgrind-out-file=%s %s %s - 256 4 1 > %s 2>&1"):format(run.quote(ctx.root),
    run.quote(data), run.quote(ctx[which]), M.SCRIPT,
    run.quote(("%s/parity-%s-callgrind.log"):format(ctx.out, which))))
  local f = io.open(data)
  if not f then return nil end
  local n = tonumber(f:read("a"):match("\nsummary: (%d+)"))
  f:close()
  os.remove(data)
  return n
end

-- ctx: {run, runstat, root, out, full, minimal, runs, quick, say}. Returns
-- the Markdown section; with quick, no instruction counts.
function M.section(ctx)
  local run, say = ctx.run, ctx.say
  local times = {full = {}, minimal = {}}
  local first = {}            -- each build's first bench line: counts, digest
  local mismatch = {}         -- runs whose counts differ from the first's
  local png = {full = ctx.out .. "/s7-full.png", minimal = ctx.out .. "/s7-minimal.png"}
  for i = 1, ctx.runs do
    -- Alternate which build goes first, so neither always runs on a cooler
    -- (or warmer) machine; each pair is still back to back.
    local order = i % 2 == 1 and {"full", "minimal"} or {"minimal", "full"}
    local got = {}
    for _, which in ipairs(order) do
      local argv = {ctx[which], M.SCRIPT}
      if i == 1 then argv[#argv + 1] = png[which] end   -- image and digest once
      local log = ("%s/parity-%s.log"):format(ctx.out, which)
      local r = run.measure(ctx.runstat, argv, ctx.root, log)
      if r.status == 0 and r.bench.trace then
        got[which] = r.bench.trace
        first[which] = first[which] or r.bench
        for _, k in ipairs(M.COUNTS) do
          if r.bench[k] ~= first[which][k] then
            mismatch[#mismatch + 1] = which .. " " .. k
          end
        end
        say("  %-7s run %d: trace %.3f s", which, i, r.bench.trace)
      else
        say("  %s failed:\n%s", which, run.tail(r.log, 6))
      end
    end
    -- Only complete pairs count: a ratio needs both halves.
    if got.full and got.minimal then
      times.full[#times.full + 1] = got.full
      times.minimal[#times.minimal + 1] = got.minimal
    end
  end

  local a, b = run.median(times.full), run.median(times.minimal)
  -- The median of each pair's ratio: a noisy spell slows both halves of a
  -- pair, so it cancels (the machine drifts).
  local ratios = {}
  for i = 1, #times.full do ratios[i] = times.full[i] / times.minimal[i] end
  local ratio = run.median(ratios)
  local lo, hi
  for _, q in ipairs(ratios) do
    lo, hi = math.min(lo or q, q), math.max(hi or q, q)
  end
  local F, N = first.full or {}, first.minimal or {}
  local threads = F.threads and ("%d"):format(F.threads) or "?"

  local lines = {"## What the full shading costs (S7)\n\n",
    "Trace seconds (median of ", #ratios, " interleaved pairs, ", threads,
    " threads each) of the full build and of\n",
    "`make MINIMAL=1` (`src/render/shade_minimal.c`: closest hit, point lights with one\n",
    "shadow ray each, Lambert and ambient; no plans, switches, specular, mirrors,\n",
    "emitters, cutoff or explain) on `", M.SCRIPT, "` (1024x1024, 4 spp,\n",
    "1000 spheres, 1000 triangles, 2 point lights, diffuse only). The ratio is the\n",
    "median of the pairs' ratios (range in brackets).\n\n",
    "| scene | full trace (s) | minimal trace (s) | full / minimal |",
    " target (<= 1.05x) |\n",
    "| --- | --- | --- | --- | --- |\n"}
  lines[#lines + 1] = ("| S7 diffuse | %s | %s | %s | %s |\n\n"):format(fmt(a), fmt(b),
    ratio and ("%.3fx [%.3f, %.3f]"):format(ratio, lo, hi) or "-",
    ratio and (ratio <= M.TARGET and "PASS" or "MISS") or "-")

  -- Same picture: the 8-bit PNGs, and the digest of the float image.
  local d = png_diff(png.full, png.minimal)
  local same_digest = F.digest and F.digest ~= 0 and F.digest == N.digest
  local image
  if not d then
    image = "not compared (an image is missing)"
  elseif d.max == 0 and same_digest then
    image = "identical (PNG max difference 0; float image digests equal)"
  elseif d.max == 0 then
    image = "PNGs identical, float images differ (digests " ..
      tostring(F.digest) .. " and " .. tostring(N.digest) .. ")"
  else
    image = ("DIFFERENT: max %.0f/255, mean %.4f/255, %.4f %% of pixels, " ..
             "worst at (%d, %d)"):format(d.max * 255, d.mean * 255,
             100 * (1 - d.within), d.worst_x, d.worst_y)
  end
  lines[#lines + 1] = "- image: " .. image .. "\n"

  -- Same rays: every counter of every run equal, and equal across builds.
  local function counts(t)
    return ("camera %s, shadow %s, reflection %s, total %s; " ..
            "%s primitive and %s node tests"):format(fmt(t.camera, "%d"),
            fmt(t.shadow, "%d"), fmt(t.reflection, "%d"), fmt(t.rays, "%d"),
            fmt(t.ptests, "%d"), fmt(t.ntests, "%d"))
  end
  local differ = {}
  for _, k in ipairs(M.COUNTS) do
    if F[k] == nil or F[k] ~= N[k] then differ[#differ + 1] = k end
  end
  lines[#lines + 1] = "- rays, full: " .. counts(F) .. "\n"
  lines[#lines + 1] = "- rays, minimal: " .. counts(N) .. "\n"
  local between = #mismatch > 0 and "; between runs: " .. table.concat(mismatch, ", ")
  lines[#lines + 1] = "- counts: " .. (#differ == 0 and #mismatch == 0 and
    "equal in both builds and every run" or
    ("MISMATCH (%s%s)"):format(table.concat(differ, ", "), between or "")) .. "\n"

  if not ctx.quick then
    say("  instructions under callgrind (about 10 s a build)")
    local fi, mi = instructions(ctx, "full"), instructions(ctx, "minimal")
    local counted = fi and mi and ("full %d, minimal %d: %.4fx"):format(fi, mi, fi / mi)
    lines[#lines + 1] = "- instructions in the render loop (callgrind, 256x256, " ..
      "4 spp, 1 thread): " .. (counted or "not counted (no valgrind)") .. "\n"
  end
  return table.concat(lines) .. "\n"
end

return M
