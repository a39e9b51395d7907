-- lancer.watch: what lancer --watch adds to each run of the script (the
-- command, src/cli/main_watch.c, runs it again in a fresh state whenever a
-- file it read changes). It notes the files the script loads through
-- dofile, loadfile and require (M.files, read by the command after the
-- run), and draws each render in the terminal pass by pass, at the top of
-- the screen with a status line under it. A run that fails before it
-- renders leaves the screen as it was: the last good picture, the error
-- printed under it.
local preview = require "lancer.preview"

local M = {files = {}, tty = false}

-- Replaced by the lancer command with one that asks the terminal.
function M.terminal_size() return nil end

local function note(path)
  if type(path) == "string" then M.files[#M.files + 1] = path end
end

local function can_draw()
  return M.tty and preview.wanted()
end

-- The picture at the top of the screen (cleared first on a render's first
-- pass), then one status line.
local function draw(img, clear, status)
  local cols, rows = M.terminal_size()
  local text = preview.text(img, {columns = cols or 80, rows = (rows or 24) - 3,
                                  truecolor = preview.truecolor()})
  io.write(clear and "\27[H\27[2J" or "\27[H", text, "\27[K", status, "\n")
  io.flush()
end

local drawn = nil       -- the last pass drawn of the render under way

local function on_pass(img, pass, stats)
  if not can_draw() then return end
  draw(img, pass == 1, ("%s: pass %d, %.4g samples per pixel, %.2f s"):format(
    M.script, pass, stats.samples / (img.width * img.height), stats.seconds))
  drawn = {passes = pass, samples = stats.samples}
end

local function on_render(img, stats)
  local last = drawn
  drawn = nil
  local status = ("%s: %dx%d, %d passes, %.2f s"):format(M.script, img.width,
    img.height, stats.passes, stats.seconds)
  if can_draw() then
    draw(img, not (last and last.passes == stats.passes and last.samples == stats.samples),
         status)
  else
    print(status)
  end
end

-- Called by the lancer command before the script runs.
function M.start(tty, terminal_size)
  M.tty = tty
  if terminal_size then M.terminal_size = terminal_size end
  local host = require "lancer.host"
  M.script = host.options.script or "the script"
  host.on_pass, host.on_render = on_pass, on_render
  local dofile0, loadfile0 = dofile, loadfile
  _G.dofile = function(path, ...)
    note(path)
    return dofile0(path, ...)
  end
  _G.loadfile = function(path, ...)
    note(path)
    return loadfile0(path, ...)
  end
  -- require's Lua searcher returns the loader and the file it found.
  local search = package.searchers[2]
  package.searchers[2] = function(name, ...)
    local loader, path = search(name, ...)
    if type(loader) == "function" then note(path) end
    return loader, path
  end
end

return M
