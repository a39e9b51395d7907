-- test_sandbox.lua: what the lancer command refuses to run: binary chunks,
-- through the built command.
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
