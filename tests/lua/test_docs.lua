-- test_docs.lua: runs every fenced code block of README.md and
-- docs/manual.md, so the documentation cannot drift from the code; and
-- checks that the manual names every option, function, method and field.
--
-- The convention. A fence's info string is a language and words:
--
--   ```lua [cont] [full] [file=NAME]     a Lua script
--   ```sh | ```bash [full] [file=NAME] [needs=PROG] [slurm] [norun=KEY]
--   ```c [file=NAME]                     a whole C program
--   ```text output [numbers]             what the block before it prints
--   ```text                              a transcript: "$ " or "> " lines
--   ```text file=NAME                    a data file later blocks use
--   ```text norun=KEY                    shown, not run (a formula, ...)
--
-- Every block runs in a fresh folder holding examples/, scenes/, tools/,
-- lua/, docs/, src/ and build/ of the repository (relative paths resolve as from
-- the repository's top) and every file=NAME block seen before it in the
-- same Markdown file. `lancer` on PATH (and build/bin/lancer there) is the
-- built command with `--width 32 --height 24 --samples 1` put first, so
-- renders are tiny whatever the block asks (a later option still wins);
-- `full` runs the block without them.
--
-- lua    written to scene.lua (or NAME) and run as `lancer scene.lua`; it
--        must exit 0. `cont`: continues the previous lua block of the file;
--        the chain from its last block without `cont` runs as one script.
-- sh     the block is a shell script run by sh -e (bash for ```bash); it
--        must exit 0. needs=PROG: skipped when PROG is not installed.
--        slurm: run as task 0 of a 12-task Slurm array (the environment
--        variables a job script reads), without sbatch.
-- c      compiled with -Isrc against build/liblancer.a and what it links (libpng,
--        OpenEXRCore: build/lancer-uninstalled.pc), run; it
--        must exit 0.
-- text output: the block before it (lua, sh or c) printed this, stdout
--        then stderr. `numbers`: every number may differ (measurements).
-- text   a shell transcript: each "$ " line runs as written (no size
--        options) and the lines up to the next "$ " are its output; or a
--        REPL session: "> " and ">> " lines are typed into `lancer -i`
--        (a first "$ lancer" line stands for that), the others are what it
--        prints, the banner included. Outputs are compared line by line:
--        trailing spaces and blank lines are ignored, a line "..." matches
--        any number of lines, "..." within a line any text, and a time
--        (0.041 s, 0.12s, 3.45 Mrays/s) any time.
-- norun=KEY: not run. KEY must be in NORUN below, which says why; the
--        commands of a norun sh block must exist, and every lancer option
--        they use must be one `lancer --help` lists.
-- pending=KEY (any block): the block shows a change known to be coming
--        (PENDING below). It must fail today, and is reported as skipped;
--        once it passes the test fails, saying the mark is to go.
--
-- Anything else fails: a fence without a language, an unknown language or
-- word, a ```text block that is none of the above, a block that fails.
local T = require "harness"
local docblocks = require "docblocks"

local q = T.quote

local DOCS = {"README.md", "docs/manual.md"}

-- Blocks shown but not run, and why.
local NORUN = {
  make = "runs the build or the whole test suite itself (make demo, make test, make bench)",
  apt = "installs system packages",
  ssh = "needs render hosts reachable over ssh",
  sbatch = "needs a Slurm cluster: test_slurm.lua starts one and runs these blocks there; " ..
           "here the job script itself runs as task 0",
  listing = "a listing or a formula, not a program",
}

-- Changes known to be coming (issue 10, made on another branch): blocks
-- marked pending=KEY show the behaviour they bring.
local PENDING = {
  ["repl-multiline"] = "the prompt prints the value of an expression typed over several lines",
}

-- Repository folders a block's folder links to.
local LINKED = {"examples", "scenes", "tools", "lua", "docs", "src"}
local SMALL = "--width 32 --height 24 --samples 1"

local function output_of(cmd)
  local p = assert(io.popen(cmd))
  local s = p:read("a")
  p:close()
  return s
end

local ROOT = output_of("pwd"):gsub("\n$", "")
local LANCER = output_of("readlink -f " .. q(T.lancer)):gsub("\n$", "")
local BUILD = LANCER:gsub("/bin/lancer$", "")

local function have(prog)
  return os.execute("command -v " .. q(prog) .. " >/dev/null 2>&1") == true
end

-- A fresh folder for one block; files: {name = text} written into it.
local function workspace(files)
  local dir = T.temp_dir()
  local sh = {"cd " .. q(dir)}
  for _, d in ipairs(LINKED) do sh[#sh + 1] = ("ln -s %s %s"):format(q(ROOT .. "/" .. d), d) end
  sh[#sh + 1] = "mkdir -p build/bin"
  sh[#sh + 1] = ("ln -s %s build/lancer"):format(q(BUILD .. "/lancer"))
  sh[#sh + 1] = ("ln -s %s build/liblancer.a"):format(q(BUILD .. "/liblancer.a"))
  -- What the manual links C programs with: PKG_CONFIG_PATH=build pkg-config lancer.
  sh[#sh + 1] = ("ln -s %s build/lancer-uninstalled.pc"):format(
    q(BUILD .. "/lancer-uninstalled.pc"))
  assert(os.execute(table.concat(sh, " && ")), "cannot set up " .. dir)
  T.write(dir .. "/build/bin/lancer", ([[
#!/bin/sh
# The built lancer, rendering tiny unless LANCER_DOCS_FULL is set.
if [ -n "${LANCER_DOCS_FULL:-}" ]; then exec %s "$@"; fi
exec %s %s "$@"
]]):format(q(LANCER), q(LANCER), SMALL))
  assert(os.execute("chmod +x " .. q(dir .. "/build/bin/lancer")))
  for name, text in pairs(files) do
    local sub = name:match("^(.*)/[^/]*$")
    if sub then os.execute("mkdir -p " .. q(dir .. "/" .. sub)) end
    T.write(dir .. "/" .. name, text)
  end
  return dir
end

-- Runs a shell command line in dir with the docs' environment.
local function run_in(dir, cmd, opts)
  opts = opts or {}
  local env = ("cd %s && export HOME=%s PATH=%s:\"$PATH\" LC_ALL=C %s%s&& "):format(
    q(dir), q(dir), q(dir .. "/build/bin"), opts.full and "LANCER_DOCS_FULL=1 " or "",
    opts.env or "")
  return T.run(env .. cmd, opts.stdin)
end

local function where(b) return ("%s:%d"):format(b.file, b.line) end

-- ---- Reading the files -------------------------------------------------------

local LANGS = {lua = true, sh = true, bash = true, c = true, text = true}
local WORDS = {
  lua = {cont = true, full = true, file = true, pending = true},
  sh = {full = true, file = true, needs = true, slurm = true, norun = true, pending = true},
  c = {pending = true, file = true},
  text = {output = true, numbers = true, norun = true, pending = true, file = true},
}
WORDS.bash = WORDS.sh

-- Checks one block's info string; returns the kind of text block.
local function check_info(b)
  if b.lang == "" then error(where(b) .. ": a fence without a language", 0) end
  if not LANGS[b.lang] then
    error(("%s: unknown language %q"):format(where(b), b.lang), 0)
  end
  for w in pairs(b.words) do
    if not WORDS[b.lang][w] then
      error(("%s: unknown word %q for %s"):format(where(b), w, b.lang), 0)
    end
  end
  local nr, pend = b.words.norun, b.words.pending
  if nr ~= nil and not NORUN[nr] then
    error(("%s: norun=%s is not in NORUN"):format(where(b), tostring(nr)), 0)
  end
  if pend ~= nil and not PENDING[pend] then
    error(("%s: pending=%s is not in PENDING"):format(where(b), tostring(pend)), 0)
  end
  if b.lang == "text" and not nr then
    local first = b.body[1] or ""
    if b.words.output then return "output" end
    if b.words.file then return "file" end
    if first:match("^%$ ") or first:match("^> ") then return "transcript" end
    error(where(b) .. ": a text block must be an output (```text output), a transcript " ..
          "(\"$ \" or \"> \" lines), a file (file=NAME) or norun=KEY", 0)
  end
end

local function read_doc(path)
  local text = assert(T.slurp(path), "cannot read " .. path)
  return docblocks.parse(text, path), text
end

-- ---- Running one block -------------------------------------------------------

-- Fails with the output's first difference from the block `out` shows.
local function compare(out, actual, what)
  local ok, why = docblocks.matches(out.body, actual, out.words.numbers)
  if not ok then
    error(("%s: the output differs from %s\n  %s\n-- actual output:\n%s"):format(
      where(out), what, why, actual), 0)
  end
end

-- Maps "scene.lua:N:" in a message to the Markdown line it came from.
local function to_doc_lines(msg, name, linemap)
  return (msg:gsub(name:gsub("%p", "%%%0") .. ":(%d+):", function(n)
    local at = linemap[tonumber(n)]
    return at and (name .. ":" .. n .. " (" .. at .. "):") or nil
  end))
end

-- A chain of lua blocks (one script); outs[i]: the output block after
-- chain[i], if any. Between blocks the script writes a marker to stdout
-- and stderr, so each block's output is compared on its own.
local function run_lua(chain, outs, files)
  local head = chain[1]
  local name = head.words.file or "scene.lua"
  local src, linemap = {}, {}
  local MARK = "\1docs\1"
  for i, b in ipairs(chain) do
    if i > 1 then
      src[#src + 1] = ("io.stdout:write(%q); io.stderr:write(%q)"):format(MARK .. "\n", MARK .. "\n")
    end
    for k, l in ipairs(b.body) do
      src[#src + 1] = l
      linemap[#src] = ("%s:%d"):format(b.file, b.line + k)
    end
  end
  local text = table.concat(src, "\n") .. "\n"
  local fs = {}
  for k, v in pairs(files) do fs[k] = v end
  fs[name] = text
  local dir = workspace(fs)
  local out, err, code = run_in(dir, "lancer " .. q(name), {full = head.words.full})
  if code ~= 0 then
    error(("%s: %s exited %d\n%s%s"):format(where(head), name, code, out,
      to_doc_lines(err, name, linemap)), 0)
  end
  local function split(s)
    local parts = {}
    for p in (s .. MARK .. "\n"):gmatch("(.-)" .. MARK .. "\n") do parts[#parts + 1] = p end
    return parts
  end
  local so, se = split(out), split(err)
  for i, b in ipairs(chain) do
    if outs[i] then compare(outs[i], (so[i] or "") .. (se[i] or ""), where(b)) end
  end
  os.execute("rm -rf " .. q(dir))
end

local function run_sh(b, out, files)
  if b.words.needs and not have(b.words.needs) then
    T.skip(b.words.needs .. " is not installed")
  end
  local dir = workspace(files)
  T.write(dir .. "/block.sh", table.concat(b.body, "\n") .. "\n")
  local shell = b.lang == "bash" and "bash" or "sh -e"
  local env = b.words.slurm and "SLURM_ARRAY_TASK_ID=0 SLURM_ARRAY_TASK_COUNT=12 " ..
    "SLURM_ARRAY_JOB_ID=1 SLURM_JOB_ID=1 " or ""
  local so, se, code = run_in(dir, shell .. " block.sh", {full = b.words.full, env = env})
  if code ~= 0 then
    error(("%s: exited %d\nstdout: %s\nstderr: %s"):format(where(b), code, so, se), 0)
  end
  if out then compare(out, so .. se, where(b)) end
  os.execute("rm -rf " .. q(dir))
end

-- A core built with make SAN=1 links only with the sanitizers' runtime.
local SANITIZED = os.execute(("nm %s 2>/dev/null | grep -q __asan_"):format(
  q(BUILD .. "/liblancer.a"))) == true

local function run_c(b, out)
  local dir = workspace({["prog.c"] = table.concat(b.body, "\n") .. "\n"})
  local cc = ("cc -std=c99 -Wall -Wextra -Werror -D_POSIX_C_SOURCE=200809L %s-I%s -o prog prog.c " ..
              "%s $(PKG_CONFIG_PATH=%s pkg-config --libs lancer)"):format(
              SANITIZED and "-fsanitize=address,undefined " or "", q(ROOT .. "/src"),
              q(BUILD .. "/liblancer.a"), q(BUILD))
  local so, se, code = run_in(dir, cc)
  if code ~= 0 then error(("%s: does not compile\n%s%s"):format(where(b), so, se), 0) end
  so, se, code = run_in(dir, "./prog")
  if code ~= 0 then
    error(("%s: the program exited %d\nstdout: %s\nstderr: %s"):format(where(b), code, so, se), 0)
  end
  if out then compare(out, so .. se, where(b)) end
  os.execute("rm -rf " .. q(dir))
end

-- "$ cmd" lines and the output after each; "> " lines go to lancer -i.
local function run_transcript(b, files)
  local first = b.body[1]
  local repl = first:match("^> ") or first:match("^%$ lancer%s*$")
  local dir = workspace(files)
  if repl then
    local input, expected = {}, {}
    for k, l in ipairs(b.body) do
      if k == 1 and l:match("^%$ lancer%s*$") then
        -- the banner follows
      elseif l:match("^>> ") or l == ">>" then
        input[#input + 1] = l:sub(4)
      elseif l:match("^> ") or l == ">" then
        input[#input + 1] = l:sub(3)
      else
        expected[#expected + 1] = l
      end
    end
    -- stdbuf: one stream, in the order a terminal would show it.
    local so, se, code = run_in(dir, "{ stdbuf -oL -eL lancer -i 2>&1; }",
                                {full = true, stdin = table.concat(input, "\n") .. "\n"})
    if code ~= 0 then
      error(("%s: the session exited %d\n%s%s"):format(where(b), code, so, se), 0)
    end
    if not first:match("^%$ ") then          -- no banner shown: drop it
      so = so:gsub("^lancer [^\n]*\n", "")
    end
    compare({body = expected, words = b.words, file = b.file, line = b.line}, so, "the session")
  else
    local k = 1
    while k <= #b.body do
      local cmd = b.body[k]:match("^%$ (.*)$")
      if not cmd then error(("%s: line %d: a command line starts with '$ '"):format(
        where(b), k), 0) end
      local expected = {}
      k = k + 1
      while k <= #b.body and not b.body[k]:match("^%$ ") do
        expected[#expected + 1] = b.body[k]
        k = k + 1
      end
      T.write(dir .. "/command.sh", cmd .. "\n")
      local so, se, code = run_in(dir, "{ stdbuf -oL -eL sh command.sh 2>&1; }", {full = true})
      if code ~= 0 then
        error(("%s: %q exited %d\n%s%s"):format(where(b), cmd, code, so, se), 0)
      end
      compare({body = expected, words = b.words, file = b.file, line = b.line}, so, cmd)
    end
  end
  os.execute("rm -rf " .. q(dir))
end

-- ---- norun blocks: their commands must exist --------------------------------

local HELP = select(1, T.run(q(T.lancer) .. " --help"))

local function make_targets()
  local t = {}
  for line in io.lines("Makefile") do
    local names = line:match("^%.PHONY:(.*)$")
    if names then for n in names:gmatch("%S+") do t[n] = true end end
  end
  return t
end

local function check_norun(b)
  if b.lang == "text" then return end
  local targets = make_targets()
  local text = table.concat(b.body, "\n"):gsub("\\\n", " ")
  for line in (text .. "\n"):gmatch("(.-)\n") do
    line = line:gsub("%s+#.*$", "")
    line = line:gsub("^(%s*)%u[%w_]*=%$%(", "%1")     -- VAR=$(prog ...): prog is the command
    if not line:match("^%s*#") and line:match("%S") then
      local words = {}
      for w in line:gmatch("%S+") do words[#words + 1] = w end
      local i = 1
      while words[i] and words[i]:match("^%u[%w_]*=") do i = i + 1 end   -- VAR=value
      if words[i] == "sudo" then i = i + 1 end
      local prog = words[i]
      if prog == "make" then
        for j = i + 1, #words do
          local w = words[j]
          if not w:match("=") and not w:match("^%-") then
            assert(targets[w], ("%s: make %s: no such target in the Makefile"):format(where(b), w))
          end
        end
      elseif prog and prog ~= "sbatch" then
        assert(have(prog) or prog == "lancer",
               ("%s: %s is not installed here"):format(where(b), prog))
      end
      for opt in line:gmatch("lancer%s+(.-)$") do
        for o in opt:gmatch("%f[%S](%-%-[%w-]+)") do
          assert(HELP:find(o, 1, true), ("%s: lancer %s is not in lancer --help"):format(where(b), o))
        end
      end
    end
  end
end

-- ---- The cases: one per runnable block ----------------------------------------

-- Wraps a job for a pending block: it must fail, and is then a skip.
local function with_pending(b, job, outs)
  local pend = b.words.pending
  for _, o in pairs(outs or {}) do
    if o.words.pending then b, pend = o, o.words.pending end
  end
  if not pend then return job end
  return function()
    local ok, why = pcall(job)
    if ok then
      error(("%s: passes now: remove pending=%s (%s)"):format(where(b), pend, PENDING[pend]), 0)
    end
    if type(why) == "table" and why.skip then error(why, 0) end
    T.skip(("pending=%s: %s"):format(pend, PENDING[pend]))
  end
end

local function register(path)
  local ok, blocks = pcall(read_doc, path)
  if not ok then
    T.test(path .. ": its fences parse", function() error(blocks, 0) end)
    return
  end
  -- First pass: the kind of each block, lua chains, and which output block
  -- goes with which runnable block.
  local jobs, files = {}, {}
  local chain, last_run = nil, nil     -- the open lua chain; the last lua/sh/c job
  for _, b in ipairs(blocks) do
    local ok2, kind = pcall(check_info, b)
    local snapshot = {}
    for k, v in pairs(files) do snapshot[k] = v end
    if not ok2 then
      jobs[#jobs + 1] = {b = b, fail = kind}
    elseif b.words.norun then
      jobs[#jobs + 1] = {b = b, run = function() check_norun(b) end}
    elseif b.lang == "lua" and b.words.cont then
      if not chain then
        jobs[#jobs + 1] = {b = b, fail = where(b) .. ": cont, but no lua block before it"}
      elseif b.words.pending or b.words.full or b.words.file then
        jobs[#jobs + 1] = {b = b, fail = where(b) .. ": pending, full and file go on a " ..
                           "chain's first block, not on cont"}
      else
        chain.blocks[#chain.blocks + 1] = b
        chain.files = snapshot             -- the files defined before its last block
        last_run = {chain = chain, index = #chain.blocks}
      end
    elseif b.lang == "lua" then
      chain = {blocks = {b}, outs = {}, files = snapshot}
      jobs[#jobs + 1] = {b = b, chain = chain}
      last_run = {chain = chain, index = 1}
    elseif b.lang == "sh" or b.lang == "bash" or b.lang == "c" then
      local job = {b = b, files = snapshot}
      jobs[#jobs + 1] = job
      last_run = {job = job}
    elseif kind == "output" then
      if not last_run then
        jobs[#jobs + 1] = {b = b, fail = where(b) .. ": an output block follows no lua, sh or c block"}
      elseif last_run.chain then
        if last_run.chain.outs[last_run.index] then
          jobs[#jobs + 1] = {b = b, fail = where(b) .. ": a second output block for one block"}
        end
        last_run.chain.outs[last_run.index] = b
      else
        if last_run.job.out then
          jobs[#jobs + 1] = {b = b, fail = where(b) .. ": a second output block for one block"}
        end
        last_run.job.out = b
      end
    elseif kind == "transcript" then
      jobs[#jobs + 1] = {b = b, transcript = true, files = snapshot}
    end
    if b.words.file then files[b.words.file] = table.concat(b.body, "\n") .. "\n" end
  end
  -- Second pass: one case per job.
  for _, j in ipairs(jobs) do
    local b = j.b
    local name, run = ("%s: %s block"):format(where(b), b.info), nil
    if j.fail then
      local msg = j.fail
      run = function() error(msg, 0) end
    elseif j.run then
      run = j.run
    elseif j.chain then
      local c = j.chain
      if #c.blocks > 1 then
        name = ("%s: lua block and %d continuing it (to line %d)"):format(where(b),
          #c.blocks - 1, c.blocks[#c.blocks].line)
      end
      run = function() run_lua(c.blocks, c.outs, c.files) end
    elseif j.transcript then
      run = function() run_transcript(b, j.files) end
    elseif b.lang == "c" then
      run = function() run_c(b, j.out) end
    else
      run = function() run_sh(b, j.out, j.files) end
    end
    if not j.fail then run = with_pending(b, run, j.chain and j.chain.outs or {j.out}) end
    T.test(name, run)
  end
end

for _, path in ipairs(DOCS) do register(path) end

-- ---- What the manual must name ------------------------------------------------

local MANUAL = T.slurp("docs/manual.md") or ""
local README = T.slurp("README.md") or ""

local function word_in(text, w)
  return text:find("%f[%w_]" .. w:gsub("%p", "%%%0") .. "%f[^%w_]") ~= nil
end

T.test("docs: the manual names every option lancer --help lists", function()
  local missing = {}
  for o in HELP:gmatch("%f[%S](%-%-?[%w][%w-]*)") do
    if not MANUAL:find("`" .. o, 1, true) and not MANUAL:find(" " .. o .. " ", 1, true) then
      missing[#missing + 1] = o
    end
  end
  assert(#missing == 0, "not in docs/manual.md: " .. table.concat(missing, ", "))
end)

-- Not for users: the command line's channel into the module (going away)
-- and the table the motion helpers come from.
local INTERNAL = {overrides = true, motion = true, _VERSION = true}

T.test("docs: the manual names every function, method and field of the module", function()
  local lancer = require "lancer"
  local missing = {}
  for k in pairs(lancer) do
    if not INTERNAL[k] and not MANUAL:find("lancer." .. k, 1, true) then
      missing[#missing + 1] = "lancer." .. k
    end
  end
  local reg = debug.getregistry()
  for _, class in ipairs{"lancer.Scene", "lancer.Image", "lancer.Mesh", "lancer.Transform"} do
    local mt = reg[class]
    local methods = type(mt.__index) == "table" and mt.__index or mt.methods or {}
    for m in pairs(methods) do
      if not MANUAL:find(":" .. m .. "[({]") then missing[#missing + 1] = class .. ":" .. m end
    end
  end
  -- Fields: each constructor's "unknown field" message lists what it knows.
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, -3}, at = {0, 0, 0}}}
  local img = lancer.image{width = 1, height = 1}
  local calls = {
    sphere = lancer.sphere, quad = lancer.quad, box = lancer.box, plane = lancer.plane,
    triangle = lancer.triangle, mesh = lancer.mesh, material = lancer.material,
    point_light = lancer.point_light, camera = lancer.camera, scene = lancer.scene,
    image = lancer.image, animate = lancer.animate,
    render = function(t) return s:render(t) end, explain = function(t) return s:explain(t) end,
    save = function(t) return img:save("unused.png", t) end,
    load_png = function(t) return lancer.load_png("unused.png", t) end,
    load_obj = function(t) return lancer.load_obj("unused.obj", t) end,
  }
  for what, f in pairs(calls) do
    local _, msg = pcall(f, {qqqqqqqqqqqq = 1})
    local list = tostring(msg):match("fields are ([%w_, ]+)")
    assert(list, what .. ": no list of fields in: " .. tostring(msg))
    for field in list:gmatch("[%w_]+") do
      if not word_in(MANUAL, field) then missing[#missing + 1] = what .. "{" .. field .. "}" end
    end
  end
  table.sort(missing)
  assert(#missing == 0, "not in docs/manual.md: " .. table.concat(missing, ", "))
end)

T.test("docs: the README is short, its first scene within 60 lines", function()
  local lines = select(2, README:gsub("\n", "\n"))
  assert(lines <= 250, ("README.md has %d lines; at most 250"):format(lines))
  local blocks = docblocks.parse(README, "README.md")
  local first
  for _, b in ipairs(blocks) do
    if b.lang == "lua" and not b.words.cont then first = b; break end
  end
  assert(first, "no lua block in README.md")
  local body = table.concat(first.body, "\n")
  assert(body:find("require", 1, true) and body:find(":render", 1, true) and
         body:find("save", 1, true), "README.md's first lua block is no whole scene")
  assert(first.line + #first.body + 1 <= 60,
         ("README.md's first scene ends on line %d, after line 60"):format(first.line + #first.body + 1))
end)

-- The anchors GitHub gives a Markdown file's headings.
local function anchors(text)
  local t = {}
  for h in text:gmatch("\n#+ ([^\n]+)") do
    local a = h:lower():gsub("`", ""):gsub("[^%w%- ]", ""):gsub(" ", "-")
    t[a] = true
  end
  return t
end

T.test("docs: links to files and headings resolve; every example has a row and a picture", function()
  for _, path in ipairs{"README.md", "docs/manual.md", "docs/engineering.md"} do
    local text = T.slurp(path)
    assert(text, "no " .. path)
    local base = path:match("^(.*)/") or "."
    for target, anchor in text:gmatch("%]%(([^)#]*)#?([^)]*)%)") do
      if not target:match("^%a+:") then
        local file = target == "" and path or base .. "/" .. target
        local linked = T.slurp(file)
        assert(linked, ("%s: the link %s leads nowhere"):format(path, target))
        if anchor ~= "" then
          assert(anchors("\n" .. linked)[anchor],
                 ("%s: no heading #%s in %s"):format(path, anchor, file))
        end
      end
    end
  end
  for script in output_of("ls examples/*.lua"):gmatch("examples/(%S+)%.lua") do
    assert(README:find(script .. ".lua", 1, true), "README.md: no row for " .. script)
    assert(README:find("docs/examples/" .. script .. ".png", 1, true),
           "README.md: no picture of " .. script)
    local size = output_of("wc -c < " .. q("docs/examples/" .. script .. ".png"))
    assert(tonumber(size) and tonumber(size) <= 40 * 1024,
           ("docs/examples/%s.png is %s bytes, over 40 KB"):format(script, size))
  end
end)
