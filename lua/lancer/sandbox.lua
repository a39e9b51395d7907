-- lancer.sandbox: runs an untrusted scene file under `lancer --sandbox`, in
-- a process of its own. From Lua that is the way to give a scene its own
-- memory cap and clock and keep it off the caller's state: a Lua state
-- cannot be sandboxed from inside itself (its string metatable, its
-- allocator and its clock are shared). The sandbox is src/cli/main_sandbox.c;
-- docs/manual.md, "Untrusted scenes: the sandbox", says what it refuses.
--
--   local sandbox = require "lancer.sandbox"
--   local ok, why, code = sandbox.run{script = "inbox/scene.lua", out = "renders",
--                                     max_memory = 512, max_seconds = 60,
--                                     log = "renders/scene.log"}
local M = {}

local FIELDS = {script = "string", out = "string", max_memory = "number",
                max_seconds = "number", args = "table", options = "table",
                lancer = "string", log = "string"}

local function quote(s) return "'" .. s:gsub("'", [['\'']]) .. "'" end

-- Raised at the line that called command or run (words is called by them).
local function bad(fname, msg)
  error(("bad argument #1 to '%s' (%s)"):format(fname, msg), 4)
end

-- The checked spec's words: lancer (default "lancer", the command on PATH),
-- --sandbox, --sandbox-out, the caps, options (more of lancer's own, such
-- as {"--width", "320"}), the script and args (what the script sees in arg).
local function words(spec, fname)
  if type(spec) ~= "table" then bad(fname, "table expected, got " .. type(spec)) end
  for k, v in pairs(spec) do
    if not FIELDS[k] then bad(fname, ("unknown field '%s'"):format(tostring(k))) end
    if type(v) ~= FIELDS[k] then
      bad(fname, ("field '%s': %s expected, got %s"):format(k, FIELDS[k], type(v)))
    end
  end
  if not spec.script then bad(fname, "field 'script': required, got nil") end
  local w = {spec.lancer or "lancer", "--sandbox"}
  local function add(...) for _, s in ipairs{...} do w[#w + 1] = tostring(s) end end
  if spec.out then add("--sandbox-out", spec.out) end
  for _, cap in ipairs{"max_memory", "max_seconds"} do
    local v = spec[cap]
    if v then
      if not (v >= 0) then
        bad(fname, ("field '%s': must be >= 0, got %s"):format(cap, v))
      end
      if cap == "max_memory" and v % 1 ~= 0 then
        bad(fname, ("field 'max_memory': megabytes are whole, got %s"):format(v))
      end
      add("--" .. cap:gsub("_", "-"), cap == "max_memory" and ("%d"):format(v) or v)
    end
  end
  for _, o in ipairs(spec.options or {}) do add(o) end
  add("--", spec.script)
  for _, a in ipairs(spec.args or {}) do add(a) end
  return w
end

local function quoted(w)
  for i, s in ipairs(w) do w[i] = quote(s) end
  return table.concat(w, " ")
end

-- The command line, quoted for sh.
function M.command(spec) return quoted(words(spec, "command")) end

-- Runs it, its output going where the caller's goes, or with log = PATH
-- both its stdout and stderr into that file: true, or nil, a sentence and
-- the exit status (1 a script error or a cap's out of memory, 2 a usage
-- error, 4 the time cap).
function M.run(spec)
  local cmd = quoted(words(spec, "run"))
  if spec.log then cmd = cmd .. " > " .. quote(spec.log) .. " 2>&1" end
  local ok, how, code = os.execute(cmd)
  if ok then return true end
  if how == "signal" then
    return nil, ("%s was killed by signal %d"):format(spec.script, code), 128 + code
  end
  return nil, ("lancer --sandbox %s exited %d%s"):format(spec.script, code,
    code == 4 and " (the time cap)" or ""), code
end

return M
