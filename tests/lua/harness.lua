-- harness.lua: the small test harness every tests/lua/test_*.lua file uses.
-- A file registers cases with T.test(name, fn); tests/lua/all.lua runs them.
local T = {cases = {}}

function T.test(name, fn)
  T.cases[#T.cases + 1] = {name = name, fn = fn, file = debug.getinfo(2, "S").short_src}
end

-- Calls f, which must raise; every further argument must appear in the message.
function T.check_error(f, ...)
  local ok, msg = pcall(f)
  assert(not ok, "no error raised")
  msg = tostring(msg)
  for _, part in ipairs{...} do
    assert(msg:find(part, 1, true), ("%q not in: %s"):format(part, msg))
  end
  return msg
end

-- Ends the running test as skipped: all.lua reports it apart, and a skip
-- never counts as passed.
local skip_mt = {__tostring = function(e) return "skipped: " .. e.skip end}
function T.skip(why)
  error(setmetatable({skip = why}, skip_mt), 0)
end

function T.near(actual, expected, tol, what)
  if not (math.abs(actual - expected) <= tol) then
    error(("%s: got %.9g, expected %.9g within %.3g"):format(
      what or "value", actual, expected, tol), 2)
  end
end

function T.eq(actual, expected, what)
  if actual ~= expected then
    error(("%s: got %s, expected %s"):format(what or "value",
      tostring(actual), tostring(expected)), 2)
  end
end

-- Counts NaN and infinite channels over a whole image.
function T.bad_pixels(img)
  local bad = 0
  for y = 1, img.height do
    for x = 1, img.width do
      local r, g, b = img:pixel(x, y)
      for _, c in ipairs{r, g, b} do
        if c ~= c or c == math.huge or c == -math.huge then bad = bad + 1 end
      end
    end
  end
  return bad
end

-- Path of the lancer command in the build tree.
T.lancer = os.getenv("LANCER_BIN") or "build/bin/lancer"

-- Runs a shell command; returns its stdout, stderr and exit code.
function T.run(cmd, stdin)
  local out, err = os.tmpname(), os.tmpname()
  local full = cmd .. " >" .. out .. " 2>" .. err
  if stdin then
    local inp = os.tmpname()
    local f = assert(io.open(inp, "w")); f:write(stdin); f:close()
    full = full .. " <" .. inp
    local ok, how, code = os.execute(full)
    os.remove(inp)
    local o, e = T.slurp(out), T.slurp(err)
    os.remove(out); os.remove(err)
    return o, e, how == "exit" and code or 128 + code
  end
  local ok, how, code = os.execute(full)
  local o, e = T.slurp(out), T.slurp(err)
  os.remove(out); os.remove(err)
  return o, e, how == "exit" and code or 128 + code
end

function T.slurp(path)
  local f = io.open(path, "rb")
  if not f then return nil end
  local s = f:read("a"); f:close()
  return s
end

-- ---- shell and files, for the tests that run the lancer command ----------

-- Quotes s for the shell.
function T.quote(s) return "'" .. s:gsub("'", [['\'']]) .. "'" end

-- A fresh empty directory (mktemp -d).
function T.temp_dir()
  local p = assert(io.popen("mktemp -d"))
  local dir = p:read("l")
  p:close()
  assert(dir and dir ~= "", "mktemp -d failed")
  return dir
end

function T.write(path, text)
  local f = assert(io.open(path, "w"))
  f:write(text)
  f:close()
end

-- Fails (naming the caller's line) unless a command exited with `want`.
function T.check_exit(code, want, out, err)
  if code ~= want then
    error(("exit %s, expected %s\nstdout: %s\nstderr: %s"):format(
      code, want, out, err), 2)
  end
end

-- Fails unless s contains part, literally.
function T.has(s, part, what)
  if not s:find(part, 1, true) then
    error(("%s: %q not in:\n%s"):format(what or "output", part, s), 2)
  end
end

-- ---- running the gallery's scripts in this process ----------------------

-- The table render is looked up in: the binding keeps Scene methods in the
-- metatable's `methods` field (its __index is a function that serves the
-- settable fields); accept a plain __index table too.
function T.scene_methods()
  local mt = debug.getregistry()["lancer.Scene"]
  assert(type(mt) == "table", "no lancer.Scene metatable in the registry")
  if type(mt.__index) == "table" then return mt.__index end
  assert(type(mt.methods) == "table", "lancer.Scene has no method table")
  return mt.methods
end

-- Runs script with arg[1] = out (or the array args), every render made at
-- size.width x size.height with size.samples (default 48x36, 1 sample)
-- and checked free of NaN and infinities; on_render(img, stats, n) sees
-- each. Returns the number of renders. Restores render, arg and print.
-- frames: for animations, the --frames ranges to render. What the script
-- writes on stderr is dropped.
function T.run_script(script, out, frames, size, on_render)
  local lancer = require "lancer"
  size = size or {width = 48, height = 36, samples = 1}
  local methods = T.scene_methods()
  local render = methods.render
  local renders = 0
  local anim = require "lancer.anim"
  local saved_options, saved_arg, saved_print = anim.options, arg, print
  methods.render = function(self, opts)
    local o = {}
    for k, v in pairs(opts or {}) do o[k] = v end
    o.width, o.height, o.samples = size.width, size.height, size.samples
    local img, stats = render(self, o)
    renders = renders + 1
    T.eq(T.bad_pixels(img), 0, script .. ": NaN/inf channels in render " .. renders)
    if on_render then on_render(img, stats, renders) end
    return img, stats
  end
  anim.options = {frames = frames}
  arg = type(out) == "table" and out or {[0] = script, [1] = out}
  print = function() end              -- scripts report what they wrote; not here
  local saved_stderr = io.stderr
  io.stderr = {write = function() end, flush = function() end}  -- frame logs, bench lines
  local ok, err = pcall(function()
    local chunk = assert(loadfile(script))
    chunk(table.unpack(arg))
  end)
  methods.render = render
  io.stderr = saved_stderr
  anim.options = saved_options
  arg = saved_arg
  print = saved_print
  if not ok then error(err, 0) end
  return renders
end

-- A 64-bit FNV-1a digest of an image's linear float channels, bit for bit.
function T.image_digest(img)
  local h = -3750763034362895579            -- 0xcbf29ce484222325
  local pack, byte = string.pack, string.byte
  for y = 1, img.height do
    local row = {}
    for x = 1, img.width do
      row[x] = pack("<fff", img:pixel(x, y))
    end
    local s = table.concat(row)
    for i = 1, #s do
      h = (h ~ byte(s, i)) * 1099511628211    -- 0x100000001b3, wrapping
    end
  end
  return ("%016x"):format(h)
end

return T
