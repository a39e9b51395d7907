-- lancer.repl: what the lancer command's prompt adds. Every render shows a
-- preview in the terminal (when standard output is one, NO_COLOR is unset
-- and TERM is not dumb) and is saved to out/repl_001.png, out/repl_002.png,
-- ..., the path printed. Globals for the prompt: lancer, show(img),
-- ls(scene). Settings live in this table (lancer.repl at the prompt):
--   repl.save = "out/repl_%03d.png"   -- or false: save nothing
--   repl.preview = true               -- false: no picture in the terminal
local lancer = require "lancer"
local preview = require "lancer.preview"
local anim = require "lancer.anim"

local M = {save = "out/repl_%03d.png", preview = true, tty = false}

-- The last number each save pattern used: a new pattern starts from its own
-- first free number, and going back to one goes on after its last.
local last = {}

-- Replaced by the lancer command with one that asks the terminal.
function M.terminal_size() return nil end

-- Why no preview can be shown here, or nil.
local function no_preview()
  if not M.tty then return "standard output is not a terminal" end
  if not preview.wanted() then return "NO_COLOR is set or TERM is dumb" end
end

local function draw(img)
  local cols, rows = M.terminal_size()
  io.write(preview.text(img, {columns = cols or 80, rows = (rows or 24) - 3,
                              truecolor = preview.truecolor()}))
  io.flush()
end

-- show(img): the image in the terminal, fitted to its width and height.
function M.show(img)
  local mt = getmetatable(img)
  if type(mt) ~= "table" or mt.__name ~= "lancer.Image" then
    local name = type(mt) == "table" and type(mt.__name) == "string" and mt.__name or
                 (img == nil and "no value" or type(img))
    error(("bad argument #1 to 'show' (lancer.Image expected, got %s)"):format(name), 2)
  end
  if tostring(img) == "lancer.Image (freed)" then
    error("bad argument #1 to 'show' (lancer.Image already freed)", 2)
  end
  local why = no_preview()
  if why then print("no preview: " .. why) else draw(img) end
end

local function exists(path)
  local f = io.open(path, "rb")
  if f then f:close() end
  return f ~= nil
end

-- The next numbered path of the pattern not taken yet, creating its folder.
local function next_path()
  local pattern, n, path = M.save, last[M.save] or 0, nil
  repeat
    n = n + 1
    path = pattern:format(n)
  until not exists(path) or not pattern:find("%", 1, true)
  last[pattern] = n
  local dir = path:match("^(.*)/[^/]*$")
  if dir and not os.rename(dir, dir) then
    os.execute("mkdir -p '" .. dir:gsub("'", [['\'']]) .. "' 2>/dev/null")
  end
  return path
end

-- lancer.host.on_render: called by every render made at the prompt.
function M.on_render(img, stats)
  if M.preview and not no_preview() then draw(img) end
  if M.save and not anim.busy then       -- animate saves its own frames
    local path = next_path()
    local ok, err = pcall(img.save, img, path)
    if ok then
      print(("saved %s (%dx%d, %.2f s)"):format(path, img.width, img.height, stats.seconds))
    else
      print("not saved: " .. tostring(err))
    end
  end
end

-- One line for an object: its own __tostring, or for a plain record its
-- fields in key order (numbers short, vectors as {x, y, z}).
local function describe(obj)
  local mt = getmetatable(obj)
  if type(obj) ~= "table" or (mt and mt.__tostring) then return tostring(obj) end
  local function show(v)
    if math.type(v) == "float" then return ("%.4g"):format(v) end
    if type(v) == "table" and #v > 0 then
      local parts = {}
      for k, x in ipairs(v) do parts[k] = show(x) end
      return "{" .. table.concat(parts, ", ") .. "}"
    end
    return tostring(v)
  end
  local keys = {}
  for k in pairs(obj) do if type(k) == "string" then keys[#keys + 1] = k end end
  table.sort(keys)
  local parts = {}
  for _, k in ipairs(keys) do parts[#parts + 1] = k .. " = " .. show(obj[k]) end
  return "{" .. table.concat(parts, ", ") .. "}"
end

-- ls(scene): the scene's objects, one per line, each with its id (#3) for
-- scene:remove(3).
function M.ls(scene)
  local name = tostring(scene)
  if not name:match("^lancer%.Scene") then
    error(("bad argument #1 to 'ls' (lancer.Scene expected, got %s)"):format(
      scene == nil and "nil" or name), 2)
  end
  print(name)
  for _, obj in ipairs(scene:objects()) do
    print("  " .. describe(obj))
  end
end

-- Called by the lancer command when the prompt starts.
function M.start(tty, terminal_size)
  M.tty = tty
  if terminal_size then M.terminal_size = terminal_size end
  require("lancer.host").on_render = M.on_render
  lancer.repl = M
  _G.lancer = _G.lancer or lancer
  _G.show = _G.show or M.show
  _G.ls = _G.ls or M.ls
end

return M
