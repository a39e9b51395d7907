-- test_sandbox.lua: what the lancer command refuses to run (binary
-- chunks) and its caps (--max-memory, --max-seconds), through the built
-- command.
local T = require "harness"

local q = T.quote

local function output_of(cmd)
  local p = assert(io.popen(cmd))
  local s = p:read("a")
  p:close()
  return s
end

local ROOT = output_of("pwd"):gsub("\n$", "")
local LANCER = T.lancer:sub(1, 1) == "/" and T.lancer or ROOT .. "/" .. T.lancer

local function now() return tonumber(output_of("date +%s%N")) / 1e9 end

-- A fresh folder: scene/ (the script's folder, an asset and links out of
-- it), out/ (the output folder, with links out of it) and secret.txt
-- beside them, outside both.
local function layout()
  local dir = T.temp_dir()
  assert(os.execute(("cd %s && mkdir scene scene/sub out && " ..
    "echo 'the secret' > secret.txt && echo 'an asset' > scene/asset.txt && " ..
    "ln -s ../secret.txt scene/link && ln -s .. scene/up && " ..
    "ln -s .. out/escape && ln -s ../made.txt out/dangling"):format(q(dir))))
  return dir
end

-- Writes script as dir/scene/scene.lua and runs `lancer OPTIONS
-- scene/scene.lua` from dir: stdout, stderr, exit status, seconds taken.
local function run(dir, options, script, args)
  if script then T.write(dir .. "/scene/scene.lua", script) end
  local t0 = now()
  local o, e, code = T.run(("cd %s && %s %s scene/scene.lua %s"):format(
    q(dir), q(LANCER), options, args or ""))
  return o, e, code, now() - t0
end

local function exists(path)
  return os.execute("test -e " .. q(path) .. " -o -L " .. q(path)) == true
end

local function cleanup(dir) os.execute("rm -rf " .. q(dir)) end

-- The probe every escape script starts with: one line per attempt,
-- "NAME REFUSED message" or "NAME ALLOWED value".
local PROBE = [[
local lancer = require "lancer"
local function probe(name, f)
  local ok, a, b = pcall(f)
  if ok and a ~= nil then print(name .. " ALLOWED " .. tostring(a))
  else print(name .. " REFUSED " .. tostring(ok and b or a)) end
end
]]

local function lines_of(out)
  local t = {}
  for name, verdict, rest in out:gmatch("(%S+) (%u+) ([^\n]*)") do
    t[name] = {verdict = verdict, msg = rest}
  end
  return t
end

-- Each name must be refused, its message naming what was refused.
local function check_refused(out, expect)
  local got = lines_of(out)
  for name, part in pairs(expect) do
    local g = got[name]
    assert(g, ("%s: no line in:\n%s"):format(name, out))
    assert(g.verdict == "REFUSED", ("%s was allowed: %s"):format(name, g.msg))
    assert(g.msg:find(part, 1, true), ("%s: %q not in %q"):format(name, part, g.msg))
  end
  return got
end

-- A binary chunk, dumped here (stock lua5.4 has string.dump).
local function write_chunk(path)
  local f = assert(io.open(path, "wb"))
  f:write(string.dump(load("print('bytecode ran', ...)")))
  f:close()
end

T.test("bytecode: load, loadfile, dofile, require, stdin take text only", function()
  local dir = layout()
  write_chunk(dir .. "/scene/chunk.luac")
  write_chunk(dir .. "/scene/binmod.lua")
  local script = PROBE .. [[
local bin = io.open("scene/chunk.luac", "rb"):read("a")
package.path = "scene/?.lua"
probe("load", function() return load(bin) end)
probe("loadfile", function() return loadfile("scene/chunk.luac") end)
probe("dofile", function() return dofile("scene/chunk.luac") or "ran" end)
probe("require", function() return require "binmod" end)
]]
  local o, e, code = run(dir, "", script)
  T.check_exit(code, 0, o, e)
  check_refused(o, {load = "binary chunks are refused (Lua does not verify them; " ..
                           "lancer --allow-bytecode allows them)",
                    loadfile = "--allow-bytecode allows them",
                    dofile = "scene/chunk.luac: binary chunks are refused",
                    require = "error loading module 'binmod'"})
  assert(not o:find("bytecode ran", 1, true), "a binary chunk ran:\n" .. o)
  o, e, code = run(dir, "--allow-bytecode", script)
  T.check_exit(code, 0, o, e)
  for _, name in ipairs{"load", "loadfile", "dofile", "require"} do
    local got = lines_of(o)[name]
    T.eq(got and got.verdict, "ALLOWED", name .. " with --allow-bytecode")
  end
  o, e, code = T.run(q(LANCER) .. " - < " .. q(dir .. "/scene/chunk.luac"))
  T.check_exit(code, 1, o, e)
  T.has(e, "lancer: stdin is a binary (precompiled) chunk, refused")
  cleanup(dir)
end)

T.test("memory cap: a huge Lua table or string fails at once, naming the cap", function()
  local dir = layout()
  local o, e, code, secs = run(dir, "--max-memory 64",
                               "local t = {} for i = 1, 1e9 do t[i] = i end")
  T.check_exit(code, 1, o, e)
  T.has(e, "lancer: not enough memory (lancer's memory cap is 64 MB)")
  assert(secs < 10, ("the cap took %.1f s"):format(secs))
  o, e, code = run(dir, "--max-memory 1024", "local s = string.rep('x', 2e9) print(#s)")
  T.check_exit(code, 1, o, e)
  T.has(e, "not enough memory (lancer's memory cap is 1024 MB)")
  -- A script may catch it, as any error, and go on: its memory is back.
  o, e, code = run(dir, "--max-memory 32", [[
local ok, err = pcall(string.rep, "x", 1e8)
print(ok, err)
local t = {} for i = 1, 1e5 do t[i] = i end
print(#t)
]])
  T.check_exit(code, 0, o, e)
  T.eq(o, "false\tnot enough memory\n100000\n", "stdout")
  cleanup(dir)
end)

T.test("memory cap: a huge image or mesh from the core fails, naming the cap", function()
  local dir = layout()
  local o, e, code = run(dir, "--max-memory 64",
    "require('lancer').image{width = 8000, height = 8000}")
  T.check_exit(code, 1, o, e)
  T.has(e, "scene/scene.lua:1: out of memory for a 8000x8000 image (lancer's memory " ..
           "cap is ")
  local f = assert(io.open(dir .. "/scene/big.obj", "w"))
  for i = 1, 300000 do f:write("v ", i, " ", i % 7, " 0\n") end
  for i = 1, 299998 do f:write("f ", i, " ", i + 1, " ", i + 2, "\n") end
  f:close()
  o, e, code = run(dir, "--max-memory 8",
                   "print(require('lancer').load_obj('scene/big.obj'))")
  T.check_exit(code, 1, o, e)
  T.has(e, "bad argument #1 to 'load_obj' (out of memory reading 'scene/big.obj' at " ..
           "line ")
  T.has(e, "(lancer's memory cap is ")
  o, e, code = run(dir, "--max-memory 64")
  T.check_exit(code, 0, o, e)
  T.eq(o, "lancer.Mesh (300000 vertices, 299998 faces)\n", "under a larger cap")
  cleanup(dir)
end)

T.test("time cap: a Lua loop stops, with pcall, coroutines or __gc around it", function()
  local dir = layout()
  for _, script in ipairs{
    "local n = 0\nwhile true do n = n + 1 end",
    "while true do pcall(function() while true do end end) end",
    "local co = coroutine.wrap(function() while true do end end)\n" ..
    "while true do pcall(co) end",
    "local function spin() while true do end end\nwhile true do xpcall(spin, spin) end",
    "setmetatable({}, {__gc = function() while true do end end}) collectgarbage()",
  } do
    local o, e, code, secs = run(dir, "--max-seconds 0.5", script)
    T.check_exit(code, 4, o, e)
    T.has(e, "time cap reached (lancer's time cap is 0.5 s)")
    assert(secs < 2, ("%q stopped after %.2f s"):format(script, secs))
  end
  -- At the line that loops.
  local o, e, code = run(dir, "--max-seconds 0.3",
                         "local x = 1\nwhile x do x = x + 1 end")
  T.check_exit(code, 4, o, e)
  T.has(e, "lancer: scene/scene.lua:2: time cap reached (lancer's time cap is 0.3 s)")
  cleanup(dir)
end)

local LONG_RENDER = [[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 1, 0}}}
s:add(lancer.sphere{center = {0, 1, 0}, radius = 1},
      lancer.point_light{position = {2, 4, -3}, intensity = 25})
print(s:render{width = 2000, height = 2000, samples = 256})
]]

-- A render stops at the core's next look between tiles (every 0.1 s):
-- measured 0.04-0.14 s late at 256 samples per pixel on 2 cores.
T.test("time cap: a long render stops within 0.5 s of the cap", function()
  local dir = layout()
  local o, e, code, secs = run(dir, "--max-seconds 1", LONG_RENDER)
  T.check_exit(code, 4, o, e)
  T.has(e, "lancer: scene/scene.lua:5: time cap reached in a render (lancer's time " ..
           "cap is 1 s)")
  assert(secs < 1.5, ("the render stopped after %.2f s"):format(secs))
  -- A frame of an animation likewise: the frames after it do not start.
  o, e, code, secs = run(dir, "--max-seconds 1", [[
local lancer = require "lancer"
lancer.animate{frames = 5, output = "out/f_%d.png",
  render = {width = 2000, height = 2000, samples = 256}, frame = function(f)
    local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 1, 0}}}
    s:add(lancer.sphere{center = {0, 1, 0}, radius = 1},
          lancer.point_light{position = {2, 4, -3}, intensity = 25})
    return s
  end}
]])
  T.check_exit(code, 4, o, e)
  T.has(e, "time cap reached (lancer's time cap is 1 s)")
  assert(not e:find("frame 2", 1, true), "a frame began after the time cap:\n" .. e)
  assert(secs < 1.5, ("the animation stopped after %.2f s"):format(secs))
  cleanup(dir)
end)

T.test("time cap: C code that does not stop ends the process 1 s after", function()
  local dir = layout()
  -- A pattern match that backtracks for hours, inside one C call.
  local o, e, code, secs = run(dir, "--max-seconds 0.5",
    "print(('a'):rep(3000):find(('.-'):rep(20) .. 'b'))")
  T.check_exit(code, 4, o, e)
  T.has(e, "lancer: time cap reached (lancer's time cap is 0.5 s), in code that " ..
           "cannot be stopped: ending the process")
  assert(secs > 1.3 and secs < 3, ("ended after %.2f s"):format(secs))
  cleanup(dir)
end)

T.test("caps: usage errors exit 2 before the script runs", function()
  local MB = "option '--max-memory' needs a whole number of megabytes (0: no cap), got "
  local S = "option '--max-seconds' needs a number of seconds from 0 (no cap) " ..
            "to 1e9, got "
  local dir = layout()
  T.write(dir .. "/scene/scene.lua", "print('the script ran')")
  for _, c in ipairs{
    {"--max-memory 12x", MB .. "'12x'"}, {"--max-memory -1", MB .. "'-1'"},
    {"--max-seconds -1", S .. "'-1'"}, {"--max-seconds nan", S .. "'nan'"},
    {"--max-seconds 0x10", S .. "'0x10'"},
    {"--max-seconds=", "option '--max-seconds' needs a value"},
    {"--max-memory=", "option '--max-memory' needs a value"},
    {"--max-seconds 5 -i", "option '--max-seconds' cannot go with the prompt"},
  } do
    local o, e, code = run(dir, c[1])
    T.check_exit(code, 2, o, e)
    T.has(e, "lancer: " .. c[2], c[1])
    T.eq(o, "", c[1] .. ": stdout")
  end
  cleanup(dir)
end)
