-- test_cli.lua: the lancer command: options, arg, exit codes, the REPL.
local T = require "harness"

local q, temp_dir, check_exit, has = T.quote, T.temp_dir, T.check_exit, T.has
local lancer = q(T.lancer)

local function write_temp(text)
  local path = os.tmpname()
  T.write(path, text)
  return path
end

T.test("--help prints usage, examples first, to stdout", function()
  local out, err, code = T.run(lancer .. " --help")
  check_exit(code, 0, out, err)
  T.eq(err, "", "stderr")
  has(out, "usage: lancer")
  local ex, opts = out:find("Examples:", 1, true), out:find("Options", 1, true)
  assert(ex and opts and ex < opts, "examples should come before the options")
end)

-- A search-replace once put C names in the help (host_report).
T.test("--help reads as prose: --check reports differing pixels", function()
  local out = T.run(lancer .. " --help")
  has(out, "away; report differing pixels, NaN and self-hits")
  assert(not out:find("host_", 1, true), "a C name in --help:\n" .. out)
end)

T.test("--version prints lancer 0.1.0 and Lua's version", function()
  local out, err, code = T.run(lancer .. " --version")
  check_exit(code, 0, out, err)
  has(out, "lancer 0.1.0")
  has(out, "Lua 5.4")
end)

T.test("a script sees arg[0], arg[1], arg[2] and ...", function()
  local path = write_temp(
    "print(arg[0], arg[1], arg[2], arg[-1] ~= nil, select('#', ...), ...)\n")
  local out, err, code = T.run(lancer .. " " .. path .. " x 'y z'")
  os.remove(path)
  check_exit(code, 0, out, err)
  T.eq(out, path .. "\tx\ty z\ttrue\t2\tx\ty z\n", "stdout")
end)

T.test("options before the script land at negative indices of arg", function()
  local path = write_temp("print(arg[-3], arg[-2], arg[-1], arg[0], #arg)\n")
  local out, err, code = T.run(lancer .. " -e 'x=1' " .. path)
  os.remove(path)
  check_exit(code, 0, out, err)
  T.eq(out, T.lancer .. "\t-e\tx=1\t" .. path .. "\t0\n", "stdout")
end)

T.test("- runs standard input with the arguments after it", function()
  local out, err, code = T.run(lancer .. " - p q",
    "print(arg[0], arg[1], arg[2], ...)\n")
  check_exit(code, 0, out, err)
  T.eq(out, "-\tp\tq\tp\tq\n", "stdout")
end)

T.test("no script and stdin not a terminal runs stdin", function()
  local out, err, code = T.run(lancer, "print(3 * 3)\n")
  check_exit(code, 0, out, err)
  T.eq(out, "9\n", "stdout")
end)

T.test("-e runs a string, and may be repeated before a script", function()
  local out, err, code = T.run(lancer .. " -e 'print(1+1)'")
  check_exit(code, 0, out, err)
  T.eq(out, "2\n", "stdout")
  local path = write_temp("print(a + b)\n")
  out, err, code = T.run(lancer .. " -e 'a = 20' -e 'b = 22' " .. path)
  os.remove(path)
  check_exit(code, 0, out, err)
  T.eq(out, "42\n", "stdout")
end)

T.test("-e code finds lancer loaded, as the prompt does", function()
  local out, err, code = T.run(lancer .. " -e " .. q("print(lancer.version, " ..
    "lancer == require 'lancer')"))
  check_exit(code, 0, out, err)
  T.eq(out, "0.1.0\ttrue\n", "stdout")
end)

T.test("a runtime error exits 1 with script:LINE: and a traceback", function()
  local path = write_temp("local x = 1\nerror('boom')\n")
  local out, err, code = T.run(lancer .. " " .. path)
  os.remove(path)
  check_exit(code, 1, out, err)
  has(err, path .. ":2: boom", "stderr")
  has(err, "stack traceback", "stderr")
  T.eq(out, "", "stdout")
end)

-- Lua names a function in a traceback after the first loaded module table
-- holding it, in an order that changes from run to run.
T.test("a traceback names 'lancer.sphere', 'lancer.lerp' in every run", function()
  local names = {}
  for _, call in ipairs{"lancer.sphere{radius = -1}", "lancer.lerp(1, {}, 0.5)",
                        "lancer.animate{frames = 0}"} do
    local path = write_temp("local lancer = require 'lancer'\n" .. call .. "\n")
    for _ = 1, 10 do
      local out, err, code = T.run(lancer .. " " .. path)
      check_exit(code, 1, out, err)
      names[err:match("in function '(lancer[%w_.]*)'") or "none"] = true
    end
    os.remove(path)
  end
  local seen = {}
  for k in pairs(names) do seen[#seen + 1] = k end
  table.sort(seen)
  T.eq(table.concat(seen, ", "), "lancer.animate, lancer.lerp, lancer.sphere",
       "names in 30 tracebacks")
end)

T.test("an error on stdin is reported as stdin:LINE:", function()
  local out, err, code = T.run(lancer .. " -", "\n\nerror('boom')\n")
  check_exit(code, 1, out, err)
  has(err, "stdin:3: boom", "stderr")
end)

T.test("an error in -e stops before the script", function()
  local out, err, code = T.run(lancer .. " -e 'error(\"early\")' -e 'print(1)'")
  check_exit(code, 1, out, err)
  has(err, "early", "stderr")
  T.eq(out, "", "stdout")
end)

T.test("an unknown option exits 2 naming it, on one line", function()
  local out, err, code = T.run(lancer .. " --frobnicate x.lua")
  check_exit(code, 2, out, err)
  has(err, "--frobnicate", "stderr")
  has(err, "try 'lancer --help'", "stderr")
  T.eq(select(2, err:gsub("\n", "")), 1, "lines on stderr")
  T.eq(out, "", "stdout")
end)

T.test("a misspelt option gets a did-you-mean hint, exit 2", function()
  for _, c in ipairs{{"--widht 100", "--widht", "--width"},
                     {"--sample=4", "--sample", "--samples"},
                     {"--frmes 1-3", "--frmes", "--frames"},
                     {"--chek", "--chek", "--check"}} do
    local out, err, code = T.run(lancer .. " " .. c[1] .. " x.lua")
    check_exit(code, 2, out, err)
    T.eq(err, ("lancer: unknown option '%s'; did you mean '%s'?\n"):format(c[2], c[3]),
         c[1] .. ": stderr")
  end
end)

-- Lua's convention: what follows the script is the script's, options too.
T.test("an option after the script goes to it, with a note on stderr", function()
  local path = write_temp("print(select('#', ...), ...)\n")
  local out, err, code = T.run(lancer .. " " .. path .. " out.png --width 100 --stats")
  check_exit(code, 0, out, err)
  T.eq(out, "4\tout.png\t--width\t100\t--stats\n", "the script's arguments")
  T.eq(err, "lancer: note: '--width' comes after the script, so the script gets it; " ..
       "put options before the script\n", "stderr")
  out, err, code = T.run(lancer .. " " .. path .. " --verbose -x out.png")
  os.remove(path)
  check_exit(code, 0, out, err)
  T.eq(err, "", "no note for what is no lancer option")
  out = T.run(lancer .. " --help")
  has(out, "lancer scene.lua out.png --width 100", "--help")
end)

T.test("bad or missing option values exit 2 naming the flag", function()
  for _, c in ipairs{
    {"--width 0", "--width"}, {"--height abc", "--height"},
    {"--samples -3", "--samples"}, {"--width", "--width"},
    {"--width 12x", "--width"}, {"-e", "-e"}} do
    local out, err, code = T.run(lancer .. " " .. c[1])
    check_exit(code, 2, out, err)
    has(err, "'" .. c[2] .. "'", c[1])
    has(err, "lancer --help", c[1])
  end
end)

T.test("a missing script exits 1 with cannot open", function()
  assert(io.open("nosuch.lua") == nil, "nosuch.lua must not exist here")
  local out, err, code = T.run(lancer .. " nosuch.lua")
  check_exit(code, 1, out, err)
  has(err, "cannot open nosuch.lua", "stderr")
end)

T.test("math.random gives the same numbers on every run", function()
  local cmd = lancer .. " -e 'print(math.random(), math.random(1, 1000000))'"
  local a, err, code = T.run(cmd)
  check_exit(code, 0, a, err)
  local b = T.run(cmd)
  assert(a:match("^0%.%d+\t%d+\n$"), "unexpected output: " .. a)
  T.eq(b, a, "second run")
end)

T.test("require 'lancer' works with no files beside the command", function()
  -- From an empty directory with no search paths: only the embedded
  -- modules can answer.
  local dir = temp_dir()
  local out, err, code = T.run(("L=$(readlink -f %s) && cd %s && " ..
    "env -u LUA_PATH -u LUA_CPATH -u LUA_PATH_5_4 -u LUA_CPATH_5_4 " ..
    "LUA_PATH=';' LUA_CPATH=';' \"$L\" -e %s"):format(lancer, q(dir),
    q("local l = require 'lancer'; print(type(l), l.version, " ..
      "type(require 'lancer.core'))")))
  os.execute("rm -rf " .. q(dir))
  check_exit(code, 0, out, err)
  T.eq(out, "table\t0.1.0\ttable\n", "stdout")
end)

T.test("--width, --height and --samples beyond the core's limits exit 2 at once", function()
  local path = write_temp("error('the script ran')\n")
  for _, c in ipairs{{"--width 2000000", "'--width': must be in [1, 1048576], got 2000000"},
                     {"--height=1048577", "option '--height': must be in [1, 1048576]"},
                     {"--samples 2000000", "option '--samples': must be in [1, "}} do
    local out, err, code = T.run(lancer .. " " .. c[1] .. " " .. path)
    check_exit(code, 2, out, err)
    has(err, c[2], c[1])
    has(err, "try 'lancer --help'", c[1])
  end
  os.remove(path)
end)

-- The script explains a pixel of its 64x48 render: under --width 8
-- --height 4 it is the pixel of the 8x4 render the command makes, and a
-- pixel outside that is an error at the script's own line.
T.test("--width and --height size explain as they size render", function()
  local scene = [[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 0, -5}, at = {0, 0, 0}}}
s:add(lancer.sphere{center = {0, 0, 0}, radius = 1})
]]
  local path = write_temp(scene .. [[
local t = s:explain{x = 7, y = 2, width = 64, height = 48}
print(("%.9f %.9f %.9f"):format(table.unpack(t.direction)))
s:explain{x = 9, y = 2, width = 64, height = 48}
]])
  local out, err, code = T.run(lancer .. " --width 8 --height 4 " .. path)
  os.remove(path)
  check_exit(code, 1, out, err)
  local L = require "lancer"
  local s = L.scene{camera = L.camera{from = {0, 0, -5}, at = {0, 0, 0}}}
  local d = s:explain{x = 7, y = 2, width = 8, height = 4}.direction
  T.eq(out, ("%.9f %.9f %.9f\n"):format(d[1], d[2], d[3]), "the 8x4 render's ray")
  has(err, path .. ":6: bad argument #1 to 'explain' (field 'x'", "stderr")
end)

T.test("--width and --height win over what the script renders", function()
  local path = write_temp([[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 0, -5}, at = {0, 0, 0}}}
s:add(lancer.sphere{center = {0, 0, 0}, radius = 1})
local img = s:render{width = 64, height = 48}
print(img.width, img.height)
]])
  local out, err, code = T.run(lancer .. " --width 8 --height 4 --samples 2 " .. path)
  os.remove(path)
  check_exit(code, 0, out, err)
  T.eq(out, "8\t4\n", "stdout")
end)

-- The REPL on a pseudo-terminal (util-linux 'script', in Debian's essential
-- bsdutils). steps are typed in order, each followed by a short pause;
-- {wait = path} waits (at most 10 s) for that file, then a little more, so
-- a keystroke lands at a known time.
-- home: a directory for HOME, or false to run with HOME unset.
local function repl(steps, home, args)
  local feed = {"sleep 0.1"}
  for _, s in ipairs(steps) do
    if type(s) == "table" then
      feed[#feed + 1] = ("n=0; while [ ! -e %s ] && [ $n -lt 200 ]; do " ..
        "sleep 0.05; n=$((n+1)); done; sleep 0.3"):format(q(s.wait))
    else
      feed[#feed + 1] = "printf '%s' " .. q(s) .. "; sleep 0.1"
    end
  end
  local env = home and "HOME=" .. q(home) or "env -u HOME"
  -- script runs "$SHELL -c CMD"; exec leaves no shell behind to die of the
  -- SIGINT the terminal sends its whole foreground group (dash would).
  local cmd = ("(%s) | %s TERM=dumb timeout 30 script -qfec %s /dev/null"):format(
    table.concat(feed, "; "), env, q("exec " .. q(T.lancer) .. (args or "")))
  local out, err, code = T.run(cmd)
  assert(code ~= 127, "cannot run util-linux 'script': " .. err)
  check_exit(code, 0, out, err)
  return out
end

T.test("REPL: an expression prints its value", function()
  local home = temp_dir()
  local out = repl({"6*7\n", "'a', nil, 2\n"}, home)
  os.execute("rm -rf " .. q(home))
  has(out, "lancer 0.1.0 (Lua 5.4)")
  assert(out:find("\n42\r?\n"), "no 42 line in:\n" .. out)
  assert(out:find("\na\tnil\t2\r?\n"), "no 'a nil 2' line in:\n" .. out)
end)

T.test("REPL: an unfinished statement reads more lines", function()
  local home = temp_dir()
  local out = repl({"for i = 1, 3 do\n", "print(i * 10)\n", "end\n"}, home)
  os.execute("rm -rf " .. q(home))
  has(out, ">> ")
  assert(out:find("\n10\r?\n20\r?\n30\r?\n"), "no 10, 20, 30 in:\n" .. out)
end)

-- The README's transcript: s:add(...) over three lines prints the scene.
T.test("REPL: an expression over several lines prints its value too", function()
  local home = temp_dir()
  local out = repl({"s = lancer.scene{}\n",
                    "s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}},\n",
                    "lancer.sphere{center = {0, 1, 0}, radius = 1},\n",
                    "lancer.point_light{position = {3, 5, -4}, intensity = 40})\n",
                    "math.max(1,\n", "2) + 40\n"}, home)
  os.execute("rm -rf " .. q(home))
  assert(out:find("\nlancer%.Scene %(2 shapes, 1 lights%)\r?\n"),
         "no lancer.Scene line after the multi-line s:add in:\n" .. out)
  assert(out:find("\n42\r?\n"), "no 42 line in:\n" .. out)
end)

T.test("REPL: history is written and read back next session", function()
  local home = temp_dir()
  repl({"6*7\n"}, home)
  local hist = T.slurp(home .. "/.lancer_history")
  assert(hist, "no " .. home .. "/.lancer_history")
  has(hist, "6*7", "history file")
  local out = repl({"\27[A\n"}, home)       -- up arrow, return: 6*7 again
  os.execute("rm -rf " .. q(home))
  assert(out:find("\n42\r?\n"), "history not recalled:\n" .. out)
end)

T.test("REPL: runs with HOME unset", function()
  local out = repl({"6*7\n"}, false)
  assert(out:find("\n42\r?\n"), "no 42 line in:\n" .. out)
end)

T.test("REPL: -i runs the script first", function()
  local home = temp_dir()
  local path = write_temp("x = 21\n")
  local out = repl({"x * 2\n"}, home, " -i " .. path)
  os.remove(path)
  os.execute("rm -rf " .. q(home))
  assert(out:find("\n42\r?\n"), "no 42 line in:\n" .. out)
end)

T.test("REPL: Ctrl-C interrupts running code and at the prompt", function()
  local home = temp_dir()
  local busy, idle = os.tmpname(), os.tmpname()
  os.remove(busy); os.remove(idle)
  local out = repl({
    ("io.open(%q, 'w'):close() while true do end\n"):format(busy),
    {wait = busy}, "\3",
    ("io.open(%q, 'w'):close()\n"):format(idle),
    {wait = idle}, "junk", "\3", "print('after')\n"}, home)
  os.remove(busy); os.remove(idle)
  os.execute("rm -rf " .. q(home))
  has(out, "interrupted!")
  assert(out:find("\nafter\r?\n"), "REPL did not go on after Ctrl-C:\n" .. out)
  assert(not out:find("junkprint"), "Ctrl-C did not clear the line:\n" .. out)
end)
