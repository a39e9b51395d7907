-- test_slurm.lua: the manual's Slurm recipes on a real Slurm. A one-node
-- cluster on localhost (munged, slurmctld and slurmd from Debian's munge and
-- slurm-wlm, a slurm.conf generated in a temporary folder, free ports) runs
-- the job scripts and the sbatch lines of docs/manual.md as written: the
-- frame array, the tile array and the merge job that waits for it. Every
-- frame and the merged frame must be byte for byte what one lancer process
-- writes. When the packages are missing, or the daemons do not come up or
-- cannot run a job here (containers often lack what slurmd needs), the case
-- is skipped, never passed; the cluster is torn down in every case.
local T = require "harness"
local docblocks = require "docblocks"

local q = T.quote

-- Renders small, so the whole run takes seconds once Slurm is up; the
-- single-process reference uses the same options.
local SIZE = "--width 64 --height 48 --samples 2"
-- The job scripts ask for 4 CPUs a task; sbatch's command line overrides
-- an #SBATCH line, so every submission asks for this many instead, and two
-- tasks share a two-CPU node.
local CPUS_PER_TASK = 1
local UP_SECONDS = 20         -- daemons up and the node idle
local PROBE_SECONDS = 30      -- a one-line job
local JOBS_SECONDS = 180      -- both arrays and the merge

local PROGS = {"munged", "munge", "unmunge", "slurmctld", "slurmd", "sbatch", "squeue",
               "sinfo", "scontrol", "scancel"}

-- Runs a command list, all of its output captured (T.run redirects only
-- the last command's).
-- The daemons live in sbin, which a plain user's PATH (or env -i's) lacks.
local SBIN = 'export PATH="$PATH:/usr/local/sbin:/usr/sbin:/sbin"; '

local function sh(cmd) return T.run("{ " .. SBIN .. cmd .. "\n}") end

local function line_of(cmd)
  local out = sh(cmd)
  return ((out or ""):gsub("%s+$", ""))
end

local function have(prog)
  return os.execute(SBIN .. "command -v " .. q(prog) .. " >/dev/null 2>&1") == true
end

local function sleep(s) os.execute("sleep " .. s) end

-- Two-byte random numbers from /dev/urandom: the suite's math.random is
-- left as the other files seeded it.
local function random_u16()
  local f = assert(io.open("/dev/urandom", "rb"))
  local a, b = f:read(2):byte(1, 2)
  f:close()
  return a * 256 + b
end

-- `n` TCP ports no socket on this machine uses (IPv4 or IPv6).
local function free_ports(n)
  local used = {}
  for _, file in ipairs{"/proc/net/tcp", "/proc/net/tcp6"} do
    for hex in (T.slurp(file) or ""):gmatch("\n%s*%d+: %x+:(%x+) ") do
      used[tonumber(hex, 16)] = true
    end
  end
  local ports = {}
  while #ports < n do
    local p = 20000 + random_u16() % 30000
    if not used[p] then used[p] = true; ports[#ports + 1] = p end
  end
  return ports
end

-- The last lines of a file, for a skip's or a failure's reason.
local function tail(path, n)
  local lines = {}
  for l in ((T.slurp(path) or "") .. "\n"):gmatch("(.-)\n") do
    if l ~= "" then lines[#lines + 1] = l end
  end
  return table.concat(lines, "\n    ", math.max(1, #lines - (n or 5) + 1))
end

-- ---- The recipes, as the manual writes them --------------------------------

-- The job scripts (```bash slurm file=NAME) and the submissions (```sh
-- norun=sbatch), in the manual's order.
local function recipes()
  local text = assert(T.slurp("docs/manual.md"), "cannot read docs/manual.md")
  local scripts, submits = {}, {}
  for _, b in ipairs(docblocks.parse(text, "docs/manual.md")) do
    if b.words.slurm and b.words.file then
      scripts[#scripts + 1] = {name = b.words.file, text = table.concat(b.body, "\n") .. "\n",
                               line = b.line}
    elseif b.words.norun == "sbatch" then
      submits[#submits + 1] = {text = table.concat(b.body, "\n") .. "\n", line = b.line}
    end
  end
  assert(#scripts > 0 and #submits > 0, "docs/manual.md: no Slurm job script or sbatch block")
  return scripts, submits
end

-- ---- A one-node cluster ------------------------------------------------------

-- Everything a command needs to talk to this cluster, and nothing inherited
-- from a Slurm the suite itself might be running under.
local function env_of(c)
  return ("unset $(env | sed -n 's/^\\(SLURM_[A-Z0-9_]*\\|SBATCH_[A-Z0-9_]*\\)=.*/\\1/p'); " ..
          "export SLURM_CONF=%s; "):format(q(c.dir .. "/slurm.conf"))
end

local function run_c(c, cmd) return sh(env_of(c) .. cmd) end

local function conf(c, node, cpus, ports, user)
  local d = c.dir
  return table.concat({
    "# A one-node cluster for tests/lua/test_slurm.lua; everything in " .. d,
    "ClusterName=lancertest",
    ("SlurmctldHost=%s(127.0.0.1)"):format(node),
    "SlurmctldPort=" .. ports[1],
    "SlurmdPort=" .. ports[2],
    "SlurmUser=" .. user,
    "SlurmdUser=" .. user,
    "AuthType=auth/munge",
    "CredType=cred/munge",
    "AuthInfo=socket=" .. d .. "/munge/munge.sock",
    "StateSaveLocation=" .. d .. "/state",
    "SlurmdSpoolDir=" .. d .. "/spool",
    "SlurmctldPidFile=" .. d .. "/slurmctld.pid",
    "SlurmdPidFile=" .. d .. "/slurmd.pid",
    "SlurmctldLogFile=" .. d .. "/log/slurmctld.log",
    "SlurmdLogFile=" .. d .. "/log/slurmd.log",
    "ProctrackType=proctrack/linuxproc",
    "TaskPlugin=task/none",
    "MpiDefault=none",
    "JobAcctGatherType=jobacct_gather/none",
    "AccountingStorageType=accounting_storage/none",
    "JobCompType=jobcomp/none",
    "SelectType=select/cons_tres",
    "SelectTypeParameters=CR_CPU",
    "ReturnToService=2",
    -- Start a freed CPU's next task within a second, not three.
    "SchedulerParameters=batch_sched_delay=0",
    -- A merge whose array failed is cancelled, not left pending for ever.
    "DependencyParameters=kill_invalid_depend",
    ("NodeName=%s NodeAddr=127.0.0.1 CPUs=%d State=UNKNOWN"):format(node, cpus),
    ("PartitionName=test Nodes=%s Default=YES MaxTime=INFINITE State=UP"):format(node),
  }, "\n") .. "\n"
end

-- why, and the daemons' last log lines.
local function with_logs(c, why)
  local logs = {}
  for _, f in ipairs{"munge/munged.log", "log/slurmctld.log", "log/slurmd.log"} do
    local t = tail(c.dir .. "/" .. f, 3)
    if t ~= "" then logs[#logs + 1] = f .. ":\n    " .. t end
  end
  return why .. (#logs > 0 and "\n  " .. table.concat(logs, "\n  ") or "")
end

-- Polls until done() is true or `seconds` pass; returns whether it was.
local function wait_for(seconds, done)
  local deadline = os.time() + seconds
  repeat
    if done() then return true end
    sleep(0.25)
  until os.time() > deadline
  return done()
end

-- The ids of the jobs queued or running, one a line; "" when none is.
local function jobs_left(c) return run_c(c, "squeue -h -o %i") or "" end

-- Starts munged, slurmctld and slurmd in c.dir; on any failure calls
-- T.skip (the caller tears down what did start).
local function start(c)
  local d = c.dir
  -- munged refuses a socket whose folders are not searchable by all.
  assert(os.execute(("chmod 755 %s && mkdir -p %s/munge %s/state %s/spool %s/log && " ..
                     "chmod 755 %s/munge"):format(q(d), q(d), q(d), q(d), q(d), q(d))))
  local key = d .. "/munge/munge.key"
  assert(os.execute(("dd if=/dev/urandom of=%s bs=1024 count=1 2>/dev/null && chmod 600 %s")
    :format(q(key), q(key))))
  local sock = d .. "/munge/munge.sock"
  local _, err, code = sh(("munged --key-file=%s --socket=%s --pid-file=%s --log-file=%s " ..
                           "--seed-file=%s"):format(q(key), q(sock), q(d .. "/munge/munged.pid"),
                           q(d .. "/munge/munged.log"), q(d .. "/munge/munged.seed")))
  if code ~= 0 then T.skip(with_logs(c, "munged does not start: " .. err:gsub("%s+$", ""))) end
  c.daemons[#c.daemons + 1] = {name = "munged", pidfile = d .. "/munge/munged.pid"}
  local _, merr, mcode = sh(("munge -n -S %s | unmunge -S %s"):format(q(sock), q(sock)))
  if mcode ~= 0 then T.skip(with_logs(c, "munge cannot encode and decode: " .. merr)) end

  local node = line_of("hostname -s")
  local cpus = tonumber(line_of("slurmd -C 2>/dev/null"):match("CPUs=(%d+)")) or
               tonumber(line_of("nproc")) or 1
  local user = line_of("id -un")
  T.write(d .. "/slurm.conf", conf(c, node, cpus, free_ports(2), user))
  c.daemons[#c.daemons + 1] = {name = "slurmctld", pidfile = d .. "/slurmctld.pid"}
  c.daemons[#c.daemons + 1] = {name = "slurmd", pidfile = d .. "/slurmd.pid"}
  local _, cerr, ccode = run_c(c, "slurmctld")
  if ccode ~= 0 then T.skip(with_logs(c, "slurmctld does not start: " .. cerr)) end
  local _, derr, dcode = run_c(c, "slurmd -N " .. q(node))
  if dcode ~= 0 then T.skip(with_logs(c, "slurmd does not start: " .. derr)) end
  c.up = true
  local state = ""
  if not wait_for(UP_SECONDS, function()
    state = (run_c(c, "sinfo -h -o %T") or ""):gsub("%s+$", "")
    return state == "idle"
  end) then
    T.skip(with_logs(c, ("the node is not idle after %d s (sinfo: %s)"):format(UP_SECONDS,
      state == "" and "nothing" or state)))
  end
  -- The daemons are up; can they run a job here?
  local out, perr, pcode = run_c(c, ("cd %s && sbatch --parsable -o probe.log --wrap true")
    :format(q(d)))
  if pcode ~= 0 then T.skip(with_logs(c, "sbatch refuses a job: " .. perr)) end
  local id = out:match("%d+")
  if not wait_for(PROBE_SECONDS, function() return jobs_left(c) == "" end) then
    T.skip(with_logs(c, ("a one-line job does not finish in %d s"):format(PROBE_SECONDS)))
  end
  local show = run_c(c, "scontrol -o show job " .. id) or ""
  if not show:find("JobState=COMPLETED", 1, true) then
    T.skip(with_logs(c, "Slurm starts but cannot run a job here: " ..
      (show:match("JobState=%S+") or show) .. " " .. (show:match("Reason=%S+") or "")))
  end
end

-- Cancels what still runs, stops the daemons by their pid files and
-- removes the folder; safe to call whatever start reached.
local function stop(c)
  if c.up then
    run_c(c, "scancel -u \"$(id -un)\" 2>/dev/null")
    wait_for(5, function() return jobs_left(c) == "" end)
  end
  -- The daemons named in their pid files, and only while the pid is still
  -- theirs; all at once, since each takes about two seconds to go.
  local pids = {}
  for _, d in ipairs(c.daemons) do
    local pid = tonumber((T.slurp(d.pidfile) or ""):match("%d+"))
    if pid and (T.slurp(("/proc/%d/comm"):format(pid)) or ""):match("^(%S+)") == d.name then
      pids[#pids + 1] = pid
    end
  end
  local function any_alive()
    for _, pid in ipairs(pids) do
      if os.execute(("kill -0 %d 2>/dev/null"):format(pid)) == true then return true end
    end
    return false
  end
  if #pids > 0 then
    os.execute(("kill %s 2>/dev/null"):format(table.concat(pids, " ")))
    if not wait_for(10, function() return not any_alive() end) then
      os.execute(("kill -9 %s 2>/dev/null"):format(table.concat(pids, " ")))
    end
  end
  os.execute("rm -rf " .. q(c.dir))
end

-- ---- The case ---------------------------------------------------------------------

-- Files below dir (relative names), leaving out the linked folders.
local function files_below(dir)
  local t = {}
  local out = sh(("cd %s && find . -path ./examples -prune -o -path ./build -prune -o " ..
                  "-path ./logs -prune -o -type f -print | sort"):format(q(dir)))
  for f in (out or ""):gmatch("%./(%S+)") do t[#t + 1] = f end
  return t
end

local function run_recipes(c)
  local root = line_of("pwd")
  local lancer = line_of("readlink -f " .. q(T.lancer))
  local scripts, submits = recipes()
  -- The folder the jobs are submitted from: examples/, the job scripts, and
  -- build/bin/lancer, the built command rendering small, on the PATH the
  -- jobs inherit; beside it sbatch, the real one with CPUS_PER_TASK first.
  local jobs, ref = c.dir .. "/jobs", c.dir .. "/ref"
  local examples = q(root .. "/examples")
  assert(os.execute(("mkdir -p %s/build/bin %s/shim %s && ln -s %s %s && ln -s %s %s"):format(
    q(jobs), q(c.dir), q(ref), examples, q(jobs), examples, q(ref))))
  T.write(jobs .. "/build/bin/lancer", ("#!/bin/sh\nexec %s %s \"$@\"\n"):format(q(lancer), SIZE))
  T.write(c.dir .. "/shim/sbatch", ("#!/bin/sh\nexec %s --cpus-per-task=%d \"$@\"\n")
    :format(q(line_of("command -v sbatch")), CPUS_PER_TASK))
  assert(os.execute(("chmod +x %s/build/bin/lancer %s/shim/sbatch"):format(q(jobs), q(c.dir))))
  for _, s in ipairs(scripts) do T.write(jobs .. "/" .. s.name, s.text) end
  local path = ("export PATH=%s:%s:\"$PATH\"; "):format(q(jobs .. "/build/bin"),
                                                        q(c.dir .. "/shim"))
  for i, s in ipairs(submits) do
    T.write(("%s/submit%d.sh"):format(jobs, i), s.text)
    local out, err, code = run_c(c, ("%scd %s && sh -e submit%d.sh"):format(path, q(jobs), i))
    if code ~= 0 then
      error(("docs/manual.md:%d: the sbatch block exited %d\n%s%s"):format(
        s.line, code, out, err), 0)
    end
  end
  -- One process renders the same while the cluster works: every frame, and
  -- the whole frame under the merged file's name.
  local _, err, code = sh(("cd %s && %s %s examples/06_orbit.lua 2>/dev/null && " ..
                           "%s %s examples/01_first_sphere.lua frame.exr")
    :format(q(ref), q(lancer), SIZE, q(lancer), SIZE))
  assert(code == 0, "the single-process render failed: " .. err)

  if not wait_for(JOBS_SECONDS, function() return jobs_left(c) == "" end) then
    error(with_logs(c, ("jobs still queued after %d s:\n%s"):format(JOBS_SECONDS,
      run_c(c, "squeue"))), 0)
  end
  -- Every job completed with exit code 0 (the probe included); a failed
  -- one is shown with the end of its log.
  local bad = {}
  local show = run_c(c, "scontrol -o show job") or ""
  for l in show:gmatch("[^\n]+") do
    if not (l:find("JobState=COMPLETED", 1, true) and l:find("ExitCode=0:0", 1, true)) then
      local function field(k) return l:match(k .. "=%S+") or k .. "=?" end
      local array, task = l:match("ArrayJobId=(%d+) ArrayTaskId=(%d+)")
      local log = tail(l:match("StdOut=(%S+)") or "", 5)
      bad[#bad + 1] = table.concat({array and "JobId=" .. array .. "_" .. task or field("JobId"),
                                    field("JobName"), field("JobState"), field("ExitCode")}, " ") ..
                      (log ~= "" and "\n    " .. log or "")
    end
  end
  if #bad > 0 then
    error("jobs that did not complete:\n  " .. table.concat(bad, "\n  "), 0)
  end
  -- The same files, byte for byte.
  local want, have_files = files_below(ref), {}
  for _, f in ipairs(files_below(jobs)) do have_files[f] = true end
  assert(#want >= 49, ("the reference holds %d files, not 48 frames and a frame"):format(#want))
  for _, f in ipairs(want) do
    assert(have_files[f], f .. ": the Slurm jobs did not write it")
    local _, _, diff = sh(("cmp -s %s %s"):format(q(ref .. "/" .. f), q(jobs .. "/" .. f)))
    assert(diff == 0, f .. ": the Slurm jobs' file differs from one process's")
  end
  local function frames(list) return select(2, table.concat(list, "\n"):gsub("out/", "")) end
  T.eq(frames(files_below(jobs)), frames(want), "frames the jobs wrote in out/")
  -- The array split them: each frame rendered by exactly one task (its
  -- log line "... -> out/NAME"), over more than one task.
  local by, tasks = {}, 0
  local logs = sh(("cd %s && ls logs"):format(q(jobs)))
  for log in logs:gmatch("%S+") do
    local any = false
    for f in (T.slurp(jobs .. "/logs/" .. log) or ""):gmatch("%-> (out/%S+)") do
      by[f] = (by[f] or 0) + 1
      any = true
    end
    if any then tasks = tasks + 1 end
  end
  for _, f in ipairs(want) do
    if f:match("^out/") then
      T.eq(by[f] or 0, 1, f .. ": tasks whose log names it")
    end
  end
  assert(tasks > 1, ("the frames came from %d task(s)"):format(tasks))
end

T.test("slurm: the manual's frame array, tile array and merge on one node " ..
       "match one process byte for byte", function()
  local missing = {}
  for _, p in ipairs(PROGS) do
    if not have(p) then missing[#missing + 1] = p end
  end
  if #missing > 0 then
    T.skip("slurm-wlm and munge are not installed (no " .. table.concat(missing, ", ") ..
           "); tools/install-deps.sh test installs them")
  end
  local c = {dir = T.temp_dir(), daemons = {}}
  local ok, err = pcall(function()
    start(c)
    run_recipes(c)
  end)
  stop(c)
  if not ok then error(err, 0) end
end)
