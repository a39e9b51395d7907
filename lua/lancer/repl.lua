-- lancer.repl: what the lancer command's prompt adds. Every render shows a
-- preview in the terminal (when standard output is one, NO_COLOR is unset
-- and TERM is not dumb) and is saved to out/repl_001.png, out/repl_002.png,
-- ..., the path printed. When a preview shows, renders are progressive and
-- the picture is redrawn after each pass; a render Ctrl-C stops keeps the
-- image of its last pass (repl.kept, saved as the others). Globals for the
-- prompt: lancer, show(img), ls(scene). Settings live in this table (lancer.repl at the prompt):
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

-- The lines of the picture last drawn, and the pass it showed (nil: none,
-- or not drawn pass by pass).
local drawn_lines, drawn = 0, nil

-- Draws img; with over, over the picture drawn last (the cursor is just
-- under it: ESC[nF goes n lines up, to their start).
local function draw(img, over)
  local cols, rows = M.terminal_size()
  local text = preview.text(img, {columns = cols or 80, rows = (rows or 24) - 3,
                                  truecolor = preview.truecolor()})
  if over and drawn_lines > 0 then io.write(("\27[%dF"):format(drawn_lines)) end
  drawn_lines = select(2, text:gsub("\n", ""))
  io.write(text)
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

-- The last pass of the render under way: {img, pass, samples}; nil when none.
local partial = nil

-- lancer.host.on_pass, while a preview can be drawn: each pass of a render
-- at the prompt redraws the picture over the last one. The image is kept
-- first, so that a Ctrl-C in the drawing still keeps it.
local function on_pass(img, pass, stats)
  partial = {img = img, pass = pass, samples = stats.samples}
  if not M.preview or no_preview() then return end
  draw(img, pass > 1)
  drawn = {passes = pass, samples = stats.samples}
end

local function save(img, what)
  if not M.save or anim.busy then return end    -- animate saves its own frames
  local path = next_path()
  local ok, err = pcall(img.save, img, path)
  if ok then
    print(("saved %s (%dx%d, %s)"):format(path, img.width, img.height, what))
  else
    print("not saved: " .. tostring(err))
  end
end

-- lancer.host.on_render: called by every render made at the prompt.
function M.on_render(img, stats)
  partial = nil
  local last = drawn
  drawn = nil
  if M.preview and not no_preview() and not (last and last.passes == stats.passes and
                                             last.samples == stats.samples) then
    draw(img)                             -- not drawn pass by pass, or not its last
  end
  save(img, ("%.2f s"):format(stats.seconds))
end

-- Called by the lancer command after a line that failed. A progressive
-- render stopped there (Ctrl-C, an error in its on_pass) leaves the image
-- of its last pass: the best so far, kept as repl.kept and saved.
function M.after_error()
  local p = partial
  partial, drawn = nil, nil
  if not p then return end
  M.kept = p.img
  local spp = p.samples / (p.img.width * p.img.height)
  print(("kept the image after pass %d (%.4g samples per pixel) as lancer.repl.kept")
    :format(p.pass, spp))
  save(p.img, ("pass %d"):format(p.pass))
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
  local host = require "lancer.host"
  host.on_render = M.on_render
  if not no_preview() then host.on_pass = on_pass end
  lancer.repl = M
  _G.lancer = _G.lancer or lancer
  _G.show = _G.show or M.show
  _G.ls = _G.ls or M.ls
end

return M
