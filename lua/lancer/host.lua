-- lancer.host: the lancer command's policy, kept out of the binding. The
-- command calls setup(options) once with its parsed command line, which
-- installs M.hook as the host hook (lancer.set_host_hook, see
-- src/lua/lua_hook.c); after the script it calls finish() for its exit status.
-- The hook:
--   * renders and explains at --width, --height, --samples, --seed, --threads;
--   * renders only the rows of --tile K/N or the pixels of --region, and
--     saves those parts beside the name the script gives (out.png becomes
--     out.tile-K-of-N.png), for lancer --merge;
--   * hands each render to lancer.check (--check) or lancer.accuracy
--     (--accuracy), and then writes none of the images the script saves:
--     its files stay as they were (check and accuracy write their own);
--   * prints each render's ledger (--stats), and gives each render to
--     M.on_render (the prompt's preview and save, lua/lancer/repl.lua, and
--     --watch's, lua/lancer/watch.lua); with M.on_pass set (by those two),
--     renders are progressive and M.on_pass sees each pass;
--   * replaces each render's progress option with --progress's;
--   * with frame options, refuses renders and saves outside lancer.animate
--     (a usage error, exit 2) before anything is written.
-- Stock lua5.4 never loads this module: require "lancer" sets no hook.
local lancer = require "lancer"
local anim = require "lancer.anim"
-- Taken now: under --sandbox (src/cli/main_sandbox.c), the scene's require loads
-- lancer's modules only and its os.exit is refused; the host's are these.
local require, exit = require, os.exit

-- setup's options: width, height, samples, seed, threads (integers or nil),
-- progress ("bar", "lines", "none" or nil), watch (--watch),
-- region ({x0, y0, x1, y1} or nil), tile ({K, N} or nil), check, stats,
-- repl (the prompt follows the script), code (-e code is run), script (its
-- name, or nil for -e code), anim (the frame options, as lancer.anim.options
-- reads them, plus first: the first frame option given) and accuracy
-- ({knobs, seeds, out, script}, for lancer.accuracy.setup).
local M = {options = {}}

local function say(msg)
  io.stderr:write("lancer: ", msg, "; try 'lancer --help'\n")
  io.stderr:flush()
end

-- A usage error found while the script runs: the command exits 2 at once.
function M.usage(msg)
  say(msg)
  exit(2, true)
end

-- --progress MODE as the render option progress.
local PROGRESS = {bar = true, none = false, lines = "lines"}

-- The options as the script gave them, with the command line's (render's
-- have a progress option, explain's none).
local function sized(opts, render)
  local o = M.options
  local progress = render and o.progress
  if not (o.width or o.height or o.samples or o.seed or o.threads or progress) then
    return opts
  end
  local t = {}
  for k, v in pairs(opts) do t[k] = v end
  t.width, t.height, t.samples = o.width or t.width, o.height or t.height,
                                 o.samples or t.samples
  t.seed, t.threads = o.seed or t.seed, o.threads or t.threads
  if progress then t.progress = PROGRESS[progress] end
  return t
end

-- The prompt and --watch draw each pass (M.on_pass, set by lancer.repl or
-- lancer.watch): the renders they see are progressive, unless the script
-- says progressive = false or asks for AOVs (which a progressive render
-- does not make), their on_pass called before the script's own. Bad values
-- are left for render to report.
local function drawn(opts)
  local draw, own = M.on_pass, opts.on_pass
  if not draw or opts.aovs ~= nil or opts.progressive == false or (opts.progressive ~= nil and
     opts.progressive ~= true) or (own ~= nil and type(own) ~= "function") then
    return opts
  end
  local t = {}
  for k, v in pairs(opts) do t[k] = v end
  t.progressive = true
  t.on_pass = function(img, pass, st)
    draw(img, pass, st)
    if own then return own(img, pass, st) end
  end
  return t
end

-- The render options with the part of the frame --region or --tile asks for.
local function part_of(opts)
  local o = M.options
  if not (o.region or o.tile) then return opts end
  local t = {}
  for k, v in pairs(opts) do t[k] = v end
  -- The core's default size (lc_render_options_default) when the script gives none.
  local w, h = math.tointeger(t.width) or 640, math.tointeger(t.height) or 480
  if o.region then
    local r = o.region
    if r[3] > w or r[4] > h then
      M.usage(("option '--region %d,%d,%d,%d' is outside the %dx%d frame"):format(
        r[1], r[2], r[3], r[4], w, h))
    end
    t.region = {r[1], r[2], r[3], r[4]}
  else
    local k, n = o.tile[1], o.tile[2]
    if n > h then
      M.usage(("option '--tile %d/%d': the %dx%d frame has fewer rows than tiles"):format(
        k, n, w, h))
    end
    t.region = {0, k * h // n, w, (k + 1) * h // n}
  end
  return t
end

-- Where a part of a frame is saved: beside the name the script gives, with
-- the part in the name before the extension.
function M.part_path(path)
  local o = M.options
  local base, ext = path:match("^(.*[^/])(%.[^./]*)$")
  if not base then return path end            -- no extension: save refuses it
  local tag = o.tile and ("tile-%d-of-%d"):format(o.tile[1], o.tile[2]) or
              ("region-%d-%d-%d-%d"):format(table.unpack(o.region))
  return base .. "." .. tag .. ext
end

-- Whether an image is a part of a frame (not the whole of it).
local function is_part(img)
  local r, f = img.region, img.frame
  return r[1] ~= 0 or r[2] ~= 0 or r[3] ~= f[1] or r[4] ~= f[2]
end

-- Frame options select frames of a lancer.animate: an image made outside
-- one is not what they ask for, so the command stops before making it
-- (not at the prompt, where renders are the point).
local function outside_animation(method)
  local o = M.options
  if o.anim and not o.repl and not anim.busy then
    M.usage(("option '%s' needs a script that calls lancer.animate{...}; %s %s " ..
             "outside one"):format(o.anim.first, o.script or "the code run",
             method == "save" and "saves an image" or "renders"))
  end
end

-- The host hook (src/lua/lua_hook.c): method is "render", "explain" or "save";
-- what is the options table, or save's path.
function M.hook(method, plain, self, what, ...)
  local o = M.options
  if method == "explain" then return plain(self, sized(what)) end
  outside_animation(method)
  if method == "save" then
    if (o.check or o.accuracy) and not M.diverted then
      local tool = o.check and "check" or "accuracy"
      io.stderr:write(("%s: not writing %s (--%s writes none of the script's " ..
                       "images)\n"):format(tool, what, tool))
      return self
    end
    if (o.region or o.tile) and is_part(self) then what = M.part_path(what) end
    return plain(self, what, ...)
  end
  local img, st
  if o.check or o.accuracy then
    -- What check and accuracy save themselves (accuracy's plot) is theirs.
    M.diverted = true
    local ok
    if o.check then
      ok, img, st = pcall(require("lancer.check").render, self, sized(what), plain)
    else
      ok, img, st = pcall(require("lancer.accuracy").render, self, what, plain, o)
    end
    M.diverted = false
    if not ok then error(img, 0) end
  else
    img, st = plain(self, drawn(part_of(sized(what, true))))
  end
  if o.stats then require("lancer.ledger").report(st) end
  if M.on_render then M.on_render(img, st) end
  return img, st
end

-- Called by the lancer command before the script: true, or nil and a
-- one-line usage error.
function M.setup(options)
  M.options = options
  if options.accuracy then
    local ok, why = require("lancer.accuracy").setup(options.accuracy)
    if not ok then return nil, why end
  end
  if options.anim then
    anim.options, anim.usage = options.anim, M.usage
  end
  anim.seed = options.seed
  if options.region or options.tile then anim.part_path = M.part_path end
  lancer.set_host_hook(M.hook)
  if options.code then _G.lancer = _G.lancer or lancer end   -- as at the prompt
  return true
end

-- After the script (before the prompt, if any): the exit status the command
-- ends with; 0 goes on. --check's verdict is 3 when unstable.
function M.finish()
  local o = M.options
  if o.anim and not o.repl and anim.count == 0 then
    say(("option '%s' needs a script that calls lancer.animate{...}; %s does not")
      :format(o.anim.first, o.script or "the code run"))
    return 2
  end
  if o.check and not require("lancer.check").finish() then return 3 end
  if o.accuracy and not require("lancer.accuracy").finish() then return 1 end
  return 0
end

return M
