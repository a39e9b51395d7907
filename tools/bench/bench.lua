-- bench.lua: `make bench`: lancer, POV-Ray 3.7 and Tachyon 0.99 on the scenes of
-- docs/bench-scenes.md, the CSG scene (scenes/csg.lua) and the glass-and-checker scene
-- (scenes/bench/glass.lua), both against POV-Ray, and Embree 3 on the same
-- rays (tools/bench/embree.lua).
--
-- Usage, from anywhere, after `make all build/bin/lc-runstat`:
--   build/bin/lancer tools/bench/bench.lua [quick] [case ...]
-- quick (or QUICK=1) runs a subset in under two minutes; case keys (b1,
-- b2-1m, ...) run just those cases; FULL=1 also runs Tachyon on B2 1M and
-- B3 4M (about 3 minutes and 8 GB for 1M spheres). The sections after the
-- cases have keys too: robust, parity, knobs (T5: cost linear in camera,
-- cone and light samples, tools/bench/knobs.lua), adaptive (T7: adaptive
-- sampling against uniform 256 spp, tools/bench/adaptive.lua), embree
-- (lancer's ray queries against Embree's, tools/bench/embree.lua), cornell
-- (the Cornell box against POV-Ray's radiosity by time to an RMSE,
-- tools/bench/cornell.lua), fixed (the fixed cost of a run beside a
-- frame's trace, tools/bench/fixed.lua).
--
-- For each case: write the POV-Ray and Tachyon files into out/bench/, then
-- run lancer, POV-Ray and Tachyon in turn (interleaved, so a noisy spell
-- hits all three), each under lc-runstat; compare the images; print the
-- table (also out/bench/results.md) and the issue's target checks.
local lancer = require "lancer"

-- Modules beside this script.
local here = (arg and arg[0] or ""):match("^(.*)/[^/]*$") or "."
local function module(name) return dofile(here .. "/" .. name .. ".lua") end
local scenes = module("scenes")
local povray = module("povray")
local tachyon = module("tachyon")
local run = module("run")
local report = module("report")
local robust = module("robust")
local parity = module("parity")
local knobs = module("knobs")
local adaptive = module("adaptive")
local embree = module("embree")
local cornell = module("cornell")
local fixed = module("fixed")

local ROOT = run.output("cd " .. run.quote(here .. "/../..") .. " && pwd")
local OUT = ROOT .. "/out/bench"
local LANCER = ROOT .. "/build/bin/lancer"
local NAIVE = ROOT .. "/build/naive/bin/lancer"    -- make NAIVE=1
local MINIMAL = ROOT .. "/build/minimal/bin/lancer" -- make MINIMAL=1
local RUNSTAT = ROOT .. "/build/bin/lc-runstat"
local RAYCAST = ROOT .. "/build/bin/lc-raycast"      -- the Embree peer

local QUICK = os.getenv("QUICK") == "1"
local ONLY = nil                      -- case keys named on the command line
for _, a in ipairs(arg or {}) do
  if a == "quick" then QUICK = true else ONLY = ONLY or {}; ONLY[a] = true end
end
local FULL = os.getenv("FULL") == "1"
local THREADS = tonumber(run.output("nproc")) or 2
-- Runs per case; lancer's are cheap, and more of them keep a noisy spell
-- (seen: 2x on B2 1M's trace) out of its median.
local LANCER_RUNS = QUICK and 3 or 5
local PEER_RUNS = QUICK and 1 or 3
local PEER_SLOW = 60                  -- s: a peer whose first run is slower runs once

-- The cases, in the order they run. lancer runs scenes/bench/<script>
-- with args plus the output path (or `path`, a script elsewhere). tachyon_full:
-- Tachyon only with FULL=1; povray_only: why Tachyon cannot draw the scene.
local CASES = {
  {key = "b1", label = "B1 1 spp", scene = scenes.b1, samples = 1,
   script = "b1.lua", args = {"1"}, quick = true},
  {key = "b1-16spp", label = "B1 16 spp", scene = scenes.b1, samples = 16,
   script = "b1.lua", args = {"16"}},
  {key = "b2-1k", label = "B2 1k spheres", scene = scenes.b2, size = 1000, samples = 1,
   script = "b2.lua", args = {"1000"}, quick = true},
  {key = "b2-10k", label = "B2 10k spheres", scene = scenes.b2, size = 10000, samples = 1,
   script = "b2.lua", args = {"10000"}},
  {key = "b2-100k", label = "B2 100k spheres", scene = scenes.b2, size = 100000,
   samples = 1, script = "b2.lua", args = {"100000"}, quick = true},
  {key = "b2-1m", label = "B2 1M spheres", scene = scenes.b2, size = 1000000, samples = 1,
   script = "b2.lua", args = {"1000000"}, tachyon_full = true},
  {key = "b3-1m", label = "B3 1M triangles", scene = scenes.b3, size = 707, samples = 1,
   script = "b3.lua", args = {"707"}, quick = true},
  {key = "b3-4m", label = "B3 4M triangles", scene = scenes.b3, size = 1414, samples = 1,
   script = "b3.lua", args = {"1414"}, tachyon_full = true},
  -- the scene classes (scenes.lua's city, clusters, mixed, instances)
  {key = "city", label = "city 19.6k boxes", scene = scenes.city, size = 160, samples = 1,
   script = "city.lua", args = {"160"}, quick = true, class = true},
  {key = "clusters", label = "clusters 100k spheres", scene = scenes.clusters,
   size = 100000, samples = 1, script = "clusters.lua", args = {"100000"}, class = true},
  {key = "mixed", label = "mixed 50k primitives", scene = scenes.mixed, size = 50000,
   samples = 1, script = "mixed.lua", args = {"50000"}, class = true},
  {key = "instances", label = "instances 400 x 1k triangles", scene = scenes.instances,
   size = 20, samples = 1, script = "instances.lua", args = {"20"}, class = true},
  -- scenes/csg.lua; Tachyon has no CSG
  {key = "csg", label = "CSG", scene = scenes.csg, samples = 1, path = "scenes/csg.lua",
   args = {"1"}, quick = true, povray_only = "no CSG"},
  -- Tachyon's transmission rays go on straight: no refraction, no index
  {key = "glass", label = "Glass + checker", scene = scenes.glass, samples = 1,
   script = "glass.lua", args = {"1"}, quick = true, povray_only = "no refraction"},
}

local function say(fmt, ...)            -- progress on stderr; stdout is the table
  io.stderr:write(fmt:format(...), "\n")
end

-- Stops with a message (no traceback: these are usage errors).
local function fail(fmt, ...)
  say("bench: " .. fmt, ...)
  os.exit(2)
end

-- The peers: how each is found, written, run and timed. ext names the scene
-- file; version is a command printing the version (Debian's package).
local PEERS = {
  {name = "povray", writer = povray, ext = "pov"},
  {name = "tachyon", writer = tachyon, ext = "dat"},
}
for _, peer in ipairs(PEERS) do
  peer.present = run.available(peer.name)
  peer.version = peer.present and
    (run.output("dpkg-query -W -f '${Version}' " .. peer.name) or "present")
end

-- One renderer's runs on one case: lists of wall, rss_mb and (lancer) its stats.
local function new_runs(status)
  return {status = status, wall = {}, rss_mb = {}, lua = {}, build = {}, trace = {},
          render = {}, rays = nil, png = nil}
end

local function record(runs, r, render_seconds)
  runs.wall[#runs.wall + 1] = r.wall
  runs.rss_mb[#runs.rss_mb + 1] = r.rss_mb
  if r.bench.trace then
    runs.lua[#runs.lua + 1] = r.bench.lua
    runs.build[#runs.build + 1] = r.bench.build
    runs.trace[#runs.trace + 1] = r.bench.trace
    runs.rays = r.bench.rays
  end
  if render_seconds then runs.render[#runs.render + 1] = render_seconds end
end

-- Runs argv once; on failure says why and marks the runs failed.
local function measure_once(runs, who, argv, dir, log, render_seconds)
  local r = run.measure(RUNSTAT, argv, dir, log)
  if not r.wall or r.status ~= 0 then
    say("  %s failed (status %s); the end of %s:\n%s", who, tostring(r.status), log,
        run.tail(r.log, 8))
    runs.status = "failed"
    return nil
  end
  record(runs, r, render_seconds and render_seconds(r.log))
  return r
end

-- Image check: a against b, both linear PNGs. Returns {mean255, within_pct}.
local function compare(a_path, b_path)
  local ok, a = pcall(lancer.load_png, a_path, {encoding = "linear"})
  local ok2, b = pcall(lancer.load_png, b_path, {encoding = "linear"})
  if not (ok and ok2) then return nil end
  local d = a:diff(b, report.IMAGE_TOL)
  return {mean255 = d.mean * 255, within_pct = d.within * 100, max255 = d.max * 255,
          worst = {d.worst_x, d.worst_y}}
end

local function run_case(case)
  local result = {case = case, lancer = new_runs("ok"), peers = {}}
  local scene = case.scene(case.size)
  say("%s", case.label)

  -- Write the peers' files (only for peers that will run).
  for _, peer in ipairs(PEERS) do
    local runs
    if not peer.present then
      runs = new_runs("missing")
    elseif peer.name ~= "povray" and case.povray_only then
      runs = new_runs("n/a")
      runs.why = case.povray_only
    elseif peer.name == "tachyon" and case.tachyon_full and not FULL then
      runs = new_runs("skipped")
    else
      runs = new_runs("ok")
      local file = ("%s/%s.%s"):format(OUT, case.key, peer.ext)
      local t0 = os.clock()
      peer.writer.write(scene, file, scenes.grid_vertex)
      say("  wrote %s (%.1f s)", file:sub(#ROOT + 2), os.clock() - t0)
      runs.max = PEER_RUNS
    end
    result.peers[peer.name] = runs
  end

  -- Interleaved: lancer, povray, tachyon, lancer, povray, tachyon, ...
  local lancer_png = ("%s/%s-lancer.png"):format(OUT, case.key)
  local argv = {LANCER, case.path or "scenes/bench/" .. case.script}
  for _, a in ipairs(case.args) do argv[#argv + 1] = a end
  argv[#argv + 1] = lancer_png
  for i = 1, LANCER_RUNS do
    local r = result.lancer.status == "ok" and
      measure_once(result.lancer, "lancer", argv, ROOT,
                   ("%s/%s-lancer.log"):format(OUT, case.key))
    if r then
      say("  lancer   run %d: %6.2f s  %6.0f MB  (trace %.3f s)", i, r.wall, r.rss_mb,
          r.bench.trace or -1)
    end
    for _, peer in ipairs(PEERS) do
      local runs = result.peers[peer.name]
      if runs.status == "ok" and i <= runs.max then
        local png = ("%s-%s.png"):format(case.key, peer.name)
        local cmd = peer.writer.command(scene, case.key .. "." .. peer.ext, png,
                                        case.samples, THREADS)
        local pr = measure_once(runs, peer.name, cmd, OUT,
                                ("%s/%s-%s.log"):format(OUT, case.key, peer.name),
                                peer.writer.render_seconds)
        if pr then
          say("  %-8s run %d: %6.2f s  %6.0f MB", peer.name, i, pr.wall, pr.rss_mb)
          runs.png = OUT .. "/" .. png
          if i == 1 and pr.wall > PEER_SLOW then runs.max = 1 end
        end
      end
    end
  end
  result.lancer.png = result.lancer.status == "ok" and lancer_png or nil

  -- Medians of every list: what the table shows.
  for _, runs in pairs{result.lancer, result.peers.povray, result.peers.tachyon} do
    runs.n = #runs.wall
    runs.med = {}
    for _, k in ipairs{"wall", "rss_mb", "lua", "build", "trace", "render"} do
      runs.med[k] = run.median(runs[k])
    end
  end

  -- Image checks against each peer's image.
  for _, peer in ipairs(PEERS) do
    local runs = result.peers[peer.name]
    if result.lancer.png and runs.png then
      runs.image = compare(result.lancer.png, runs.png)
    end
  end
  return result
end

-- Main --------------------------------------------------------------------
assert(os.execute("mkdir -p " .. run.quote(OUT)))
if not run.available(RUNSTAT) then
  fail("%s not found: run `make bench` (it builds it)", RUNSTAT)
end
local peers_line, missing = {}, false
for _, peer in ipairs(PEERS) do
  if not peer.present then
    say("%s is missing: lancer runs without it " ..
        "(install the peers with: apt-get install povray tachyon)", peer.name)
  end
  missing = missing or not peer.present
  peers_line[#peers_line + 1] = peer.name .. " " .. (peer.version or "missing")
end
if missing then
  peers_line[#peers_line + 1] = "install with: apt-get install povray tachyon"
end
local machine = {
  nproc = THREADS,
  cpu = (run.output("grep -m1 'model name' /proc/cpuinfo") or ""):match(":%s*(.*)")
        or "?",
  date = os.date("%Y-%m-%d %H:%M"),
  commit = run.output("git -C " .. run.quote(ROOT) .. " rev-parse --short HEAD") or "?",
  mode = ONLY and "selected cases" or QUICK and "quick"
         or (FULL and "full, FULL=1" or "full"),
  peers = table.concat(peers_line, ", "),
  lancer_runs = LANCER_RUNS, peer_runs = PEER_RUNS, peer_slow = PEER_SLOW,
}
for key in pairs(ONLY or {}) do
  local known = false
  for _, case in ipairs(CASES) do known = known or case.key == key end
  known = known or key == "robust" or key == "parity" or key == "knobs" or
          key == "adaptive" or key == "embree" or key == "cornell" or key == "fixed"
  if not known then
    fail("no case '%s' (cases: b1 b1-16spp b2-1k b2-10k b2-100k b2-1m b3-1m b3-4m city "
         .. "clusters mixed instances csg glass "
         .. "robust parity knobs adaptive embree cornell fixed)", key)
  end
end
local results = {}
for _, case in ipairs(CASES) do
  local wanted = ONLY and ONLY[case.key] or (not ONLY and (case.quick or not QUICK))
  if wanted then results[#results + 1] = run_case(case) end
end

local text = report.markdown(machine, results)
if not ONLY or ONLY.robust then
  if run.available(NAIVE) then
    say("robustness cost")
    text = text .. "\n" .. robust.section{run = run, runstat = RUNSTAT, root = ROOT,
      out = OUT, robust = LANCER, naive = NAIVE, runs = QUICK and 3 or 15, say = say}
  else
    say("%s not found: `make bench` builds it (make NAIVE=1)", NAIVE)
  end
end
if not ONLY or ONLY.parity then
  if run.available(MINIMAL) then
    say("cost parity (S7)")
    text = text .. "\n" .. parity.section{run = run, runstat = RUNSTAT, root = ROOT,
      out = OUT, full = LANCER, minimal = MINIMAL, runs = QUICK and 3 or 15,
      quick = QUICK, say = say}
  else
    say("%s not found: `make bench` builds it (make MINIMAL=1)", MINIMAL)
  end
end
if not ONLY or ONLY.fixed then
  say("the fixed cost of a run")
  text = text .. "\n" .. fixed.section{run = run, runstat = RUNSTAT, root = ROOT, out = OUT,
    lancer = LANCER, runs = QUICK and 3 or 7, say = say}
end
if not ONLY or ONLY.knobs then
  say("cost linear in each knob (T5)")
  text = text .. "\n" .. knobs.section{say = say, quick = QUICK}
end
if not ONLY or ONLY.adaptive then
  say("adaptive sampling (T7)")
  text = text .. "\n" .. adaptive.section{say = say, quick = QUICK}
end
if not ONLY or ONLY.embree then
  if run.available(RAYCAST) then
    say("Embree 3 on the same rays")
    text = text .. "\n" .. embree.section{run = run, runstat = RUNSTAT, root = ROOT,
      out = OUT, raycast = RAYCAST, threads = THREADS, quick = QUICK, say = say}
  else
    say("%s not found: `make bench` builds it (with Debian's libembree-dev)", RAYCAST)
  end
end
if not ONLY or ONLY.cornell then
  say("Cornell box against POV-Ray's radiosity (time to error)")
  text = text .. "\n" .. cornell.section{run = run, runstat = RUNSTAT, root = ROOT, out = OUT,
    threads = THREADS, quick = QUICK, say = say}
end
io.write(text)
io.stdout:flush()                     -- before the last line on stderr
local f = assert(io.open(OUT .. "/results.md", "w"))
f:write(text)
f:close()
say("wrote out/bench/results.md")
