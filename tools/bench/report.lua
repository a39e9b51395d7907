-- report.lua: the results table and the issue's target checks, as Markdown.
--
-- Input: bench.lua's results, one per case: {case, lancer = runs, peers =
-- {povray = runs, tachyon = runs}}, where runs has status ("ok", "missing",
-- "skipped", "failed"), n (runs done), med (medians: wall, rss_mb, lua,
-- build, trace, render), rays, image ({mean255, within_pct, ...} vs lancer).
local M = {}

local fmt = string.format

-- Image check: a pixel is "within" when every channel differs by at most
-- IMAGE_TOL. lancer and POV-Ray sample the same pixel centres, so with the
-- scene written right they differ only where a ray grazes an edge (float
-- order, 5-decimal sphere files) or, at 16 spp, where jittered and regular
-- sub-samples see an edge differently. Measured on matching scenes (2-core
-- EPYC, this commit's scenes): 1 spp mean 0.000-0.12/255 and >= 99.99 %
-- within; B1 16 spp 0.04/255 and 99.4 %. The thresholds leave room for
-- that and no more: a wrong camera handedness, gamma, falloff or ambient
-- gives a mean of several /255 and far fewer pixels within.
M.IMAGE_TOL = 2 / 255
M.IMAGE_MEAN_MAX = 0.5           -- mean |difference| x 255 (seen: <= 0.12)
M.IMAGE_WITHIN_MIN = 99.0        -- % of pixels within IMAGE_TOL (seen: >= 99.4)

local function f2(x) return x and fmt("%.2f", x) or "-" end
local function f3(x) return x and fmt("%.3f", x) or "-" end

local function by_key(results)
  local t = {}
  for _, r in ipairs(results) do t[r.case.key] = r end
  return t
end

local function image_ok(img)
  return img.mean255 <= M.IMAGE_MEAN_MAX and img.within_pct >= M.IMAGE_WITHIN_MIN
end

-- "wall / peak MB" for a peer, or why there is none.
local function peer_cell(runs, peer_runs)
  if runs.status == "missing" then return "missing" end
  if runs.status == "skipped" then return "skipped (FULL=1 runs it)" end
  if runs.status == "n/a" then
    return "n/a (" .. (runs.why or "cannot draw it") .. ")"
  end
  if not runs.med.wall then return runs.status end
  local cell = fmt("%s / %.0f", f2(runs.med.wall), runs.med.rss_mb)
  if runs.n < peer_runs then cell = cell .. fmt(" (%d run)", runs.n) end
  if runs.status == "failed" then cell = cell .. " (failed)" end
  return cell
end

local function ratio_cell(lancer, runs)
  if not (lancer.med.wall and runs.med.wall) then return "-" end
  return f2(lancer.med.wall / runs.med.wall)
end

local function image_cell(img, judge)
  if not img then return "-" end
  local cell = fmt("%.3f, %.2f %%", img.mean255, img.within_pct)
  if judge then cell = cell .. (image_ok(img) and " PASS" or " MISS") end
  return cell
end

-- A Markdown table whose columns are padded, so it reads in a terminal too.
local function table_text(header, rows)
  local width = {}
  for _, row in ipairs({header, table.unpack(rows)}) do
    for i, cell in ipairs(row) do width[i] = math.max(width[i] or 3, utf8.len(cell)) end
  end
  local function line(row)
    local cells = {}
    for i, cell in ipairs(row) do
      cells[i] = cell .. (" "):rep(width[i] - utf8.len(cell))
    end
    return "| " .. table.concat(cells, " | ") .. " |\n"
  end
  local rule = {}
  for i = 1, #header do rule[i] = ("-"):rep(width[i]) end
  local out = {line(header), line(rule)}
  for _, row in ipairs(rows) do out[#out + 1] = line(row) end
  return table.concat(out)
end

local function results_table(results, machine)
  local header = {"case", "lancer wall (s)", "build (s)", "trace (s)", "Lua scene (s)",
                  "peak MB", "Mrays/s", "POV-Ray wall (s) / MB", "Tachyon wall (s) / MB",
                  "lancer / POV-Ray", "lancer / Tachyon",
                  "image vs POV-Ray (mean x255, within)", "image vs Tachyon"}
  local rows = {}
  for _, r in ipairs(results) do
    local l, pov, tac = r.lancer, r.peers.povray, r.peers.tachyon
    local mrays = l.rays and l.med.trace and l.med.trace > 0 and
                  fmt("%.1f", l.rays / l.med.trace / 1e6) or "-"
    rows[#rows + 1] = {
      r.case.label,
      l.status == "ok" and f2(l.med.wall) or l.status,
      f3(l.med.build), f3(l.med.trace), f3(l.med.lua),
      l.med.rss_mb and fmt("%.0f", l.med.rss_mb) or "-", mrays,
      peer_cell(pov, machine.peer_runs), peer_cell(tac, machine.peer_runs),
      ratio_cell(l, pov), ratio_cell(l, tac),
      image_cell(pov.image, true), image_cell(tac.image, false),
    }
  end
  return table_text(header, rows)
end

-- The issue's targets: a list of {ok = true/false/nil, text}. nil: not measured.
local function targets(results)
  local R = by_key(results)
  local out = {}
  local function add(ok, text, ...) out[#out + 1] = {ok = ok, text = fmt(text, ...)} end
  local function lancer(key) return R[key] and R[key].lancer.med or nil end

  for _, key in ipairs{"b1", "b1-16spp"} do
    local r = R[key]
    local name = key == "b1" and "B1 1 spp" or "B1 16 spp"
    local l, t = r and r.lancer.med.wall, r and r.peers.tachyon.med.wall
    if l and t then
      add(l <= 0.8 * t, "%s: lancer wall %.2f s <= 0.8 x Tachyon wall %.2f s = %.2f s",
          name, l, t, 0.8 * t)
    else
      add(nil, "%s: lancer wall <= 0.8 x Tachyon wall (not measured)", name)
    end
  end

  local m = lancer("b2-1m")
  if m and m.wall then
    add(m.wall <= 4 and m.rss_mb <= 150,
        "B2 1M: wall %.2f s <= 4 s and peak %.0f MB <= 150 MB", m.wall, m.rss_mb)
  else
    add(nil, "B2 1M: wall <= 4 s and peak <= 150 MB (not measured)")
  end
  m = lancer("b3-1m")
  if m and m.wall then
    add(m.wall <= 2.5, "B3 1M: wall %.2f s <= 2.5 s", m.wall)
  else
    add(nil, "B3 1M: wall <= 2.5 s (not measured)")
  end
  m = lancer("b3-4m")
  if m and m.wall then
    add(m.wall <= 6 and m.rss_mb <= 450,
        "B3 4M: wall %.2f s <= 6 s and peak %.0f MB <= 450 MB", m.wall, m.rss_mb)
  else
    add(nil, "B3 4M: wall <= 6 s and peak <= 450 MB (not measured)")
  end

  -- The targets against Embree are measured in the same run, on the same
  -- rays: tools/bench/embree.lua's section.

  -- The scenes only POV-Ray draws too: lancer faster, same run.
  for _, c in ipairs{{"csg", "CSG"}, {"glass", "Glass + checker"}} do
    local r = R[c[1]]
    local l, p = r and r.lancer.med.wall, r and r.peers.povray.med.wall
    if l and p then
      add(l < p, "%s: lancer wall %.2f s < POV-Ray wall %.2f s (%.2fx); trace %.3f s, "
          .. "POV-Ray's own %.3f s", c[2], l, p, l / p, r.lancer.med.trace or 0,
          r.peers.povray.med.render or 0)
    else
      add(nil, "%s: lancer wall < POV-Ray wall (not measured)", c[2])
    end
  end

  -- The scene classes: ahead of Tachyon's own ray-tracing time (its log's
  -- "Ray Tracing Time", which leaves out its parsing and start-up).
  for _, r in ipairs(results) do
    local l, t = r.lancer.med, r.peers.tachyon.med
    if r.case.class and l.trace and t.render then
      add(l.trace < t.render, "%s: lancer trace %.3f s < Tachyon's own ray-tracing " ..
          "time %.3f s (%.2fx; walls %.2f and %.2f s)", r.case.label, l.trace, t.render,
          l.trace / t.render, l.wall, t.wall)
    elseif r.case.class then
      add(nil, "%s: lancer trace < Tachyon's own ray-tracing time (not measured)",
          r.case.label)
    end
  end

  local big, small = lancer("b2-1m"), lancer("b2-1k")
  if big and small and big.trace and small.trace then
    add(big.trace / small.trace <= 4,
        "B2: trace(1M) / trace(1k) = %.3f / %.3f = %.2f <= 4", big.trace,
        small.trace, big.trace / small.trace)
  else
    add(nil, "B2: trace(1M) / trace(1k) <= 4 (not measured)")
  end

  for _, r in ipairs(results) do
    local img = r.peers.povray.image
    if img then
      add(image_ok(img), "%s image vs POV-Ray: mean %.3f/255 <= %.1f/255 and %.2f %% " ..
          ">= %.0f %% of pixels within 2/255 (worst pixel %d,%d off by %.0f/255)",
          r.case.label, img.mean255, M.IMAGE_MEAN_MAX, img.within_pct, M.IMAGE_WITHIN_MIN,
          img.worst[1], img.worst[2], img.max255)
    end
  end
  return out
end

-- Per-run numbers, for reading the noise behind the medians.
local function raw_runs(results)
  local out = {}
  local function list(xs, digits)
    local t = {}
    for i, x in ipairs(xs) do t[i] = fmt("%." .. digits .. "f", x) end
    return table.concat(t, " ")
  end
  for _, r in ipairs(results) do
    local l = r.lancer
    out[#out + 1] = fmt("- %s: lancer wall %s s, trace %s s, build %s s; %d rays",
                        r.case.label, list(l.wall, 2), list(l.trace, 3), list(l.build, 3),
                        l.rays or 0)
    for _, name in ipairs{"povray", "tachyon"} do
      local p = r.peers[name]
      if #p.wall > 0 then
        out[#out + 1] = fmt("  - %s wall %s s, own render time %s s, peak %s MB", name,
                            list(p.wall, 2), list(p.render, 2), list(p.rss_mb, 0))
      end
    end
  end
  return table.concat(out, "\n") .. "\n"
end

-- Paragraphs under the title and under the table (one sentence a line).
local INTRO = [[
All three renderers use %d threads; times are medians of %d lancer runs and %d per
peer (a peer whose first run exceeds %d s runs once), interleaved.
Wall and peak MB are the whole process (lc-runstat); build, trace and Lua scene are
lancer's own stats. 1280x720.
16 spp: lancer 16 Owen-scrambled Sobol' points per pixel, POV-Ray a regular 4x4 grid (+A0.0 +AM1 +R4 +J0),
Tachyon the centre + 15 jittered samples.
]]
local IMAGES = [[
Image columns: mean |lancer - peer| x 255 over all channels, and the share of pixels
whose channels all differ by <= 2/255. PASS vs POV-Ray: mean <= %.1f/255 and >= %.0f %%
within. Tachyon is only reported: its pixel (i, j) is sampled at the corner (i+1, j)
of the others' grid (docs/bench-scenes.md), so every edge
differs; compared at that corner (lancer
rendered on the (W+1)x(H+1) corner grid) it matches too (B2 100k: 0.47/255, 100 %%
within).
]]

function M.markdown(machine, results)
  local out = {}
  out[#out + 1] = "# lancer benchmark (make bench)\n\n"
  out[#out + 1] = fmt("Machine: %d cores (nproc), %s; %s; lancer %s; %s run.\n" ..
                      "Peers (Debian packages): %s.\n\n", machine.nproc, machine.cpu,
                      machine.date, machine.commit, machine.mode, machine.peers)
  out[#out + 1] = fmt(INTRO, machine.nproc, machine.lancer_runs, machine.peer_runs,
                      machine.peer_slow) .. "\n"
  out[#out + 1] = results_table(results, machine)
  out[#out + 1] = "\n" .. fmt(IMAGES, M.IMAGE_MEAN_MAX, M.IMAGE_WITHIN_MIN)
  out[#out + 1] = "\n## Targets\n\n"
  for _, t in ipairs(targets(results)) do
    local mark = t.ok == nil and "n/a " or (t.ok and "PASS" or "MISS")
    out[#out + 1] = fmt("- %s  %s\n", mark, t.text)
  end
  out[#out + 1] = "\n## Runs\n\n"
  out[#out + 1] = raw_runs(results)
  return table.concat(out)
end

return M
