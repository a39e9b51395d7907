-- test_repl.lua: what the prompt adds: a preview of every render in the
-- terminal, renders saved and their path printed, Ctrl-C cancelling a
-- render, ls(scene). Driven through a pseudo-terminal (util-linux script).
local T = require "harness"
local lancer = require "lancer"
local preview = require "lancer.preview"

local q = T.quote
local temp_dir = T.temp_dir
local has = T.has

local function absolute(path)
  local p = assert(io.popen("readlink -f " .. q(path)))
  local abs = p:read("l")
  p:close()
  return abs
end

-- Runs the lancer prompt on a pseudo-terminal in a fresh folder (also its
-- HOME) with the environment `env` ("NAME=value ..."). steps are typed in
-- order with a short pause after each; {wait = path} waits (at most 10 s)
-- for that file to appear, then 0.3 s more. Returns the terminal's output,
-- the folder, and the seconds the session took.
local function repl(steps, env)
  local dir = temp_dir()
  local feed = {"sleep 0.2"}
  for _, s in ipairs(steps) do
    if type(s) == "table" then
      feed[#feed + 1] = ("n=0; while [ ! -e %s ] && [ $n -lt 200 ]; do " ..
        "sleep 0.05; n=$((n+1)); done; sleep 0.3"):format(q(s.wait))
    else
      feed[#feed + 1] = "printf '%s' " .. q(s) .. "; sleep 0.2"
    end
  end
  -- exec: no shell stays behind to die of the terminal's SIGINT.
  local cmd = ("(%s) | env -u NO_COLOR -u COLORTERM HOME=%s %s timeout 30 script -qfec %s " ..
    "/dev/null"):format(table.concat(feed, "; "), q(dir), env,
    q("cd " .. q(dir) .. " && exec " .. q(absolute(T.lancer))))
  local t0 = os.time()
  local out, err, code = T.run(cmd)
  assert(code ~= 127, "cannot run util-linux 'script': " .. err)
  if code ~= 0 then error(("exit %d\nstdout: %s\nstderr: %s"):format(code, out, err), 2) end
  return out, dir, os.time() - t0
end

local SCENE = "s = lancer.scene{camera = lancer.camera{from = {0, 0, -4}, at = {0, 0, 0}}}\n"
local ADD = "s:add(lancer.sphere{center = {0, 0, 0}, radius = 1}, " ..
            "lancer.point_light{position = {2, 4, -3}, intensity = 25})\n"
local TRUECOLOR_CELL = "\27%[38;2;%d+;%d+;%d+;48;2;%d+;%d+;%d+m\u{2580}"

T.test("REPL: a render is previewed in 24-bit colour and saved", function()
  local out, dir = repl({SCENE, ADD, "img = s:render{width = 16, height = 8}\n",
                         "img2 = s:render{width = 8, height = 4}\n"},
                        "TERM=xterm-256color COLORTERM=truecolor")
  assert(out:find(TRUECOLOR_CELL), "no truecolor half blocks in:\n" .. out)
  local _, cells = out:gsub(TRUECOLOR_CELL, "")
  T.eq(cells, 16 * 4 + 8 * 2, "cells drawn (16x4 and 8x2)")
  has(out, "saved out/repl_001.png (16x8, ")
  has(out, "saved out/repl_002.png (8x4, ")
  local png = T.slurp(dir .. "/out/repl_001.png")
  assert(png and png:sub(2, 4) == "PNG", "out/repl_001.png not written")
  os.execute("rm -rf " .. q(dir))
end)

T.test("REPL: 256 colours without COLORTERM; none with NO_COLOR or TERM=dumb", function()
  local steps = {SCENE, ADD, "img = s:render{width = 8, height = 4}\n"}
  local out, dir = repl(steps, "TERM=xterm-256color")
  os.execute("rm -rf " .. q(dir))
  local _, cells = out:gsub("\27%[38;5;%d+;48;5;%d+m\u{2580}", "")
  T.eq(cells, 8 * 2, "256-colour cells")
  assert(not out:find("38;2;", 1, true), "24-bit colour without COLORTERM")
  for _, env in ipairs{"TERM=xterm-256color COLORTERM=truecolor NO_COLOR=1", "TERM=dumb"} do
    out, dir = repl(steps, env)
    os.execute("rm -rf " .. q(dir))
    assert(not out:find("\u{2580}"), env .. ": a preview was drawn:\n" .. out)
    assert(not out:find("\27[38;", 1, true), env .. ": colour escapes:\n" .. out)
    has(out, "saved out/repl_001.png (8x4, ", env)
  end
end)

T.test("REPL: Ctrl-C cancels a render and the prompt goes on", function()
  local busy = os.tmpname()
  os.remove(busy)
  local out, dir, seconds = repl({SCENE, ADD,
    ("io.open(%q, 'w'):close(); img = s:render{width = 3000, height = 3000, samples = 64}\n")
      :format(busy),
    {wait = busy}, "\3", "print('after', img)\n"}, "TERM=dumb")
  os.remove(busy)
  has(out, "stdin:1: render cancelled")
  assert(out:find("\nafter\tnil\r?\n"), "the prompt did not go on:\n" .. out)
  assert(not T.slurp(dir .. "/out/repl_001.png"), "a cancelled render was saved")
  os.execute("rm -rf " .. q(dir))
  -- 576M camera rays take minutes here; the session took a few seconds.
  assert(seconds < 10, ("the session took %d s"):format(seconds))
end)

T.test("REPL: the preview refines pass by pass; Ctrl-C keeps the last pass", function()
  local busy = os.tmpname()
  os.remove(busy)
  -- Pass 2 of 4096 samples touches the file; the passes after it take minutes.
  local out, dir, seconds = repl({SCENE, ADD,
    "img = s:render{width = 16, height = 8, samples = 4}\n",
    ("img = s:render{width = 200, height = 100, samples = 4096, progressive = true, " ..
     "on_pass = function(_, p) " ..
     "if p == 2 then io.open(%q, 'w'):close() end end}\n"):format(busy),
    {wait = busy}, "\3", "print('kept', lancer.repl.kept, img)\n"},
    "TERM=xterm-256color COLORTERM=truecolor")
  os.remove(busy)
  -- 4 samples: passes of 1, 2 and 4, each drawn over the last (ESC[4F: the
  -- 4 lines of a 16x8 picture up), and the final image not drawn again.
  local first = out:match("samples = 4}(.-)saved out/repl_001.png")
  assert(first, "no first render in:\n" .. out)
  local _, cells = first:gsub(TRUECOLOR_CELL, "")
  T.eq(cells, 3 * 16 * 4, "cells drawn by 3 passes")
  local _, ups = first:gsub("\27%[4F", "")
  T.eq(ups, 2, "redraws over the picture")
  -- Cancelled while tracing, or interrupted in the preview's drawing.
  assert(out:find("stdin:1: render cancelled", 1, true) or out:find("interrupted!", 1, true),
         "not cancelled:\n" .. out)
  has(out, "kept the image after pass ")
  has(out, "saved out/repl_002.png (200x100, pass ")
  assert(out:find("\nkept\tlancer.Image 200x100\tlancer.Image 16x8\r?\n"),
         "repl.kept is not the image, or img was assigned:\n" .. out)
  local png = T.slurp(dir .. "/out/repl_002.png")
  assert(png and #png > 100, "the kept image was not saved")
  os.execute("rm -rf " .. q(dir))
  assert(seconds < 15, ("the session took %d s"):format(seconds))
end)

-- ---- In this process ---------------------------------------------------------

-- A render whose every pixel is the background colour.
local function flat(w, h, rgb)
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, -1}, at = {0, 0, 0}},
                         background = rgb}
  return (s:render{width = w, height = h, progress = false})
end

T.test("preview: exact cells, odd rows, fitted to the terminal", function()
  local img = flat(2, 2, {1, 0, 0.2158605})           -- sRGB (255, 0, 128)
  T.eq(preview.text(img, {columns = 80, rows = 24}),
       ("\27[38;2;255;0;128;48;2;255;0;128m\u{2580}"):rep(2) .. "\27[0m\n", "2x2 truecolor")
  T.eq(preview.text(img, {columns = 80, rows = 24, truecolor = false}),
       ("\27[38;5;199;48;5;199m\u{2580}"):rep(2) .. "\27[0m\n", "2x2 in 256 colours")
  T.eq(preview.text(flat(1, 3, 0), {}),
       "\27[38;2;0;0;0;48;2;0;0;0m\u{2580}\27[0m\n\27[38;2;0;0;0;49m\u{2580}\27[0m\n", "1x3")
  local w, h = preview.size({width = 640, height = 480}, 80, 40)
  T.eq(w .. "x" .. h, "80x60", "640x480 in 80 columns: pixels")
  w, h = preview.size({width = 640, height = 480}, 200, 20)
  T.eq(w .. "x" .. h, "53x40", "640x480 in 20 rows")
  w, h = preview.size({width = 8, height = 4}, 80, 24)
  T.eq(w .. "x" .. h, "8x4", "never wider than the image")
end)

T.test("ls(scene) lists the scene; show() says why it cannot draw", function()
  local repl = require "lancer.repl"
  local printed = {}
  local saved_print = print
  print = function(...) printed[#printed + 1] = table.concat({...}, "\t") end
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, -4}, at = {0, 0, 0}}}
  s:add(lancer.sphere{center = {0, 0, 0}, radius = 1},
        lancer.point_light{position = {2, 4, -3}, intensity = 25})
  local ok, err = pcall(repl.ls, s)
  local tty = repl.tty
  repl.tty = false
  pcall(repl.show, flat(2, 2, 0))
  repl.tty = tty
  print = saved_print
  assert(ok, err)
  T.eq(printed[1], "lancer.Scene (1 shapes, 1 lights)", "first line")
  T.eq(#printed, 1 + 2 + 1, "one line per object")
  T.eq(printed[2], "  #1 lancer.sphere{center = {0, 0, 0}, radius = 1}", "the sphere, by id")
  assert(printed[3]:match("^  #2 lancer%.point_light{"), "the light, by id: " .. printed[3])
  T.eq(printed[#printed], "no preview: standard output is not a terminal", "show")
  T.check_error(function() repl.ls(42) end, "test_repl.lua:",
                "bad argument #1 to 'ls' (lancer.Scene expected, got 42)")
end)

T.test("ls(scene): one line per object, records by their fields", function()
  local repl = require "lancer.repl"
  local fake = setmetatable({}, {__tostring = function() return "lancer.Scene (fake)" end})
  function fake.objects()
    return {{id = 4, kind = "sphere", center = {0, 0.5, 0}, radius = 1.25},
            lancer.point_light{position = {1, 2, 3}, intensity = 5}}
  end
  local printed = {}
  local saved_print = print
  print = function(...) printed[#printed + 1] = table.concat({...}, "\t") end
  local ok, err = pcall(repl.ls, fake)
  print = saved_print
  assert(ok, err)
  T.eq(#printed, 3, "lines")
  T.eq(printed[1], "lancer.Scene (fake)", "header")
  T.eq(printed[2], "  {center = {0, 0.5, 0}, id = 4, kind = sphere, radius = 1.25}", "record")
  T.eq(printed[3], "  " .. tostring(lancer.point_light{position = {1, 2, 3}, intensity = 5}),
       "object with __tostring")
end)

T.test("repl.save: a new pattern starts at its own next free number", function()
  local repl = require "lancer.repl"
  local dir = temp_dir()
  local img = flat(2, 2, 0.5)
  local printed = {}
  local saved_print, saved_save, saved_preview = print, repl.save, repl.preview
  print = function(...) printed[#printed + 1] = table.concat({...}, "\t") end
  repl.preview = false
  local ok, err = pcall(function()
    repl.save = dir .. "/out/repl_%03d.png"
    for _ = 1, 3 do repl.on_render(img, {seconds = 0}) end
    repl.save = dir .. "/renders/%03d.png"       -- an empty folder
    repl.on_render(img, {seconds = 0})
    repl.save = dir .. "/out/repl_%03d.png"      -- back: after the three there
    repl.on_render(img, {seconds = 0})
  end)
  print, repl.save, repl.preview = saved_print, saved_save, saved_preview
  assert(ok, err)
  local names = {}
  for i, line in ipairs(printed) do names[i] = line:match("^saved " .. dir:gsub("%p", "%%%0") ..
                                                          "/(%S+)") or line end
  T.eq(table.concat(names, " "), "out/repl_001.png out/repl_002.png out/repl_003.png " ..
       "renders/001.png out/repl_004.png", "paths saved")
  os.execute("rm -rf " .. q(dir))
end)
