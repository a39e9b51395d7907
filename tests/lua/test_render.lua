-- test_render.lua: threads, determinism, statistics and the progress bar.
local T = require "harness"
local lancer = require "lancer"

-- 2000 random spheres and a 50x50 height-field mesh: a real BVH.
local function busy_scene()
  local s = 7
  local function u()
    s = s * 6364136223846793005 + 1442695040888963407
    return (s >> 11) * (1.0 / 9007199254740992.0)
  end
  local scene = lancer.scene{camera = lancer.camera{from = {0, 8, 30}, at = {0, 0, 0}},
                             ambient = 0.1, background = {0.3, 0.4, 0.6}}
  local mats = {}
  for k = 1, 4 do
    mats[k] = lancer.material{color = {u(), u(), u()}, kr = k == 1 and 0.5 or 0, ks = 0.3}
  end
  for k = 1, 2000 do
    scene:add(lancer.sphere{center = {40 * u() - 20, 3 * u(), 40 * u() - 20},
                            radius = 0.1 + 0.4 * u(), material = mats[k % 4 + 1]})
  end
  local mesh, Q = lancer.mesh{}, 50
  for j = 0, Q do
    local row = {}
    for i = 0, Q do
      local x, z = -25 + 50 * i / Q, -25 + 50 * j / Q
      row[#row + 1], row[#row + 2], row[#row + 3] = x, math.sin(x * 0.3) * math.cos(z * 0.2), z
    end
    mesh:add_vertices(row)
  end
  for j = 0, Q - 1 do
    for i = 0, Q - 1 do
      local a = j * (Q + 1) + i + 1
      mesh:add_faces{a, a + 1, a + Q + 2, a, a + Q + 2, a + Q + 1}
    end
  end
  scene:add(mesh)
  scene:add(lancer.point_light{position = {10, 20, 10}, intensity = 600})
  return scene
end

T.test("the image is bit-identical across thread counts and runs", function()
  local scene = busy_scene()
  local opts = {width = 96, height = 64, samples = 4}
  local ref, st = scene:render{width = 96, height = 64, samples = 4, threads = 1}
  for _, n in ipairs{2, 3, 8} do
    opts.threads = n
    local d = ref:diff(scene:render(opts), 0)
    T.eq(d.max, 0, ("largest difference with %d threads"):format(n))
  end
  opts.threads = 2
  T.eq(ref:diff(scene:render(opts), 0).max, 0, "a second run")
  T.eq(st.threads, 1, "threads used")
  T.eq(T.bad_pixels(ref), 0, "NaN or infinite pixels")
end)

T.test("statistics count the hierarchy and the primitives", function()
  local scene = busy_scene()
  local _, st = scene:render{width = 8, height = 8}
  T.eq(st.primitives, 2000 + 2 * 50 * 50, "spheres plus triangles")
  assert(st.bvh_nodes > 100 and st.bvh_nodes < 2 * st.primitives,
         "node count " .. st.bvh_nodes)
  assert(st.compile_seconds > 0, "the first render builds the hierarchy")
  local _, again = scene:render{width = 8, height = 8}
  assert(again.compile_seconds < st.compile_seconds,
         "an unchanged scene is not rebuilt: " .. again.compile_seconds)
  scene:add(lancer.sphere{center = {0, 50, 0}, radius = 1})
  local _, after = scene:render{width = 8, height = 8}
  T.eq(after.primitives, st.primitives + 1, "a new sphere is traced")
end)

-- A script whose render takes a few tenths of a second at one thread.
local SLOW = [[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 0, -4}, at = {0, 0, 0}}}
for i = 1, 100 do
  s:add(lancer.sphere{center = {math.sin(i), math.cos(i), i * 0.01}, radius = 0.5,
                      material = lancer.material{kr = 0.5}})
end
s:add(lancer.point_light{position = {0, 3, -3}, intensity = 9})
s:render{width = 200, height = 150, samples = 16, threads = 1, progress = PROGRESS}
]]

local function run_slow(progress)
  local path = os.tmpname()
  local f = assert(io.open(path, "w"))
  f:write((SLOW:gsub("PROGRESS", progress)))
  f:close()
  local out, err, code = T.run(T.lancer .. " " .. path)
  os.remove(path)
  T.eq(code, 0, "exit status; stderr: " .. err)
  return err
end

T.test("progress: a bar with the time left when asked, nothing when not", function()
  local err = run_slow("true")
  assert(err:find("[#", 1, true) and err:find("% ", 1, true) and err:find("left", 1, true),
         "no progress bar in: " .. err)
  assert(err:sub(-4) == "\r\27[K", "the bar is cleared at the end")
  -- stderr is a file here, not a terminal: the default draws nothing.
  T.eq(run_slow("nil"), "", "stderr without a terminal")
end)

-- ---- the host hook (lancer.set_host_hook) ------------------------------------

local HERE = "test_render.lua:"

local function lit_scene()
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, -4}, at = {0, 0, 0}}}
  s:add(lancer.sphere{center = {0, 0, 0}, radius = 2},
        lancer.point_light{position = {2, 4, -3}, intensity = 25})
  return s
end

-- Runs f with hook set, and always takes it away again.
local function with_hook(hook, f)
  local before = lancer.set_host_hook(hook)
  local ok, err = pcall(f)
  lancer.set_host_hook(before)
  if not ok then error(err, 0) end
end

T.test("require 'lancer' in lua5.4 sets no host hook and loads no host policy", function()
  local out, err, code = T.run("lua5.4 -e " .. T.quote(
    "local l = require 'lancer'; l.scene{camera = l.camera{from = {0, 0, 1}, " ..
    "at = {0, 0, 0}}}:render{width = 1, height = 1}; " ..
    "print(l.set_host_hook(nil), package.loaded['lancer.host'], l.overrides)"))
  T.check_exit(code, 0, out, err)
  T.eq(out, "nil\tnil\tnil\n", "hook, lancer.host, lancer.overrides")
end)

T.test("set_host_hook: render, explain and save go through it, after their checks", function()
  local seen = {}
  local path = os.tmpname() .. ".png"
  local function hook(method, plain, self, ...)
    seen[#seen + 1] = method .. " " .. tostring(self):match("^%S+")
    if method == "render" then
      local opts = ...
      T.eq(type(opts), "table", "render's options, {} for none")
      local o = {}
      for k, v in pairs(opts) do o[k] = v end
      o.width, o.height = 6, 4               -- what the lancer command's --width does
      return plain(self, o)
    end
    return plain(self, ...)
  end
  local s = lit_scene()
  with_hook(hook, function()
    local img, st = s:render{width = 64, height = 48}
    T.eq(img.width .. "x" .. img.height, "6x4", "the hook's options")
    T.eq(st.rays.camera, 24, "statistics of the hook's render")
    s:render()
    T.eq(s:explain{x = 1, y = 1, width = 4, height = 4}.kind, "camera", "explain")
    T.eq(img:save(path), img, "save returns the image")
    T.check_error(function() s:render{widht = 4} end, HERE, "'render'", "did you mean")
  end)
  T.eq(table.concat(seen, ","), "render lancer.Scene,render lancer.Scene," ..
       "explain lancer.Scene,save lancer.Image", "calls seen")
  assert(T.slurp(path), "plain save wrote nothing")
  os.remove(path)
end)

T.test("set_host_hook: plain's failures read as the script's, as with no hook", function()
  local img = lit_scene():render{width = 2, height = 2}
  local s = lancer.scene{}
  local function messages()
    return {
      select(2, pcall(function() s:render{width = 2, height = 2} end)),
      select(2, pcall(function() img:save("/nonexistent-lancer-dir/x.png") end)),
      select(2, pcall(function() lit_scene():explain{x = 9, y = 1, width = 2,
                                                     height = 2} end)),
    }
  end
  local plain = messages()
  local hooked
  with_hook(function(method, run, ...) return run(...) end, function()
    hooked = messages()
  end)
  for i = 1, 3 do
    assert(plain[i]:find(HERE, 1, true), plain[i])
    T.eq(hooked[i], plain[i], "message " .. i)
  end
  local has_field = plain[3]:find("bad argument #1 to 'explain' (field 'x'", 1, true)
  assert(has_field, plain[3])
  -- Caught by the hook, the error is a value whose tostring is the message.
  local caught
  with_hook(function(method, run, ...)
    local ok, e = pcall(run, ...)
    caught = tostring(e)
    error(e)
  end, function()
    T.check_error(function() img:save("/nonexistent-lancer-dir/x.png") end, HERE,
                  "bad argument #1 to 'save'", "cannot write")
  end)
  assert(caught:find("^cannot write '/nonexistent%-lancer%-dir/x%.png'"), caught)
end)

T.test("set_host_hook: a hook that raises refuses the call; nil takes it away", function()
  local s = lit_scene()
  with_hook(function() error("not now", 0) end, function()
    T.check_error(function() s:render{width = 2, height = 2} end, "not now")
  end)
  local img = s:render{width = 2, height = 2}
  T.eq(img.width, 2, "rendered once the hook is gone")
  T.check_error(function() lancer.set_host_hook(5) end, HERE, "'set_host_hook'",
                "function expected, got number")
end)

-- ---- warnings ------------------------------------------------------------------

local function warning_scene(kind)
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, -4}, at = {0, 0, 0}}}
  local black = lancer.material{color = {0, 0, 0}}
  s:add(lancer.sphere{center = {0, 0, 0}, radius = 2,
                      material = kind == "black" and black or nil})
  if kind ~= "dark" then
    s:add(lancer.point_light{position = {2, 4, -3}, intensity = 25})
  end
  return s
end

T.test("stats.warning: no light at all, or every pixel black; nil when fine", function()
  local _, st = warning_scene("dark"):render{width = 4, height = 4}
  assert(st.warning and st.warning:find("^the scene has no light"), tostring(st.warning))
  _, st = warning_scene("black"):render{width = 4, height = 4}
  assert(st.warning and st.warning:find("^every pixel is black"), tostring(st.warning))
  _, st = warning_scene("lit"):render{width = 4, height = 4}
  T.eq(st.warning, nil, "a lit scene's warning")
end)

-- One Lua warning per render, from the binding (lua5.4) as from the
-- command (through its host hook, --check's four renders included).
T.test("a render's warning is one line on stderr, not an error", function()
  local script = os.tmpname() .. ".lua"
  T.write(script, ([[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 0, -4}, at = {0, 0, 0}}}
s:add(lancer.sphere{center = {0, 0, 0}, radius = 2, material = %s})
if arg[1] ~= "dark" then
  s:add(lancer.point_light{position = {2, 4, -3}, intensity = 25})
end
s:render{width = 4, height = 4}
print("went on")
]]):format("arg[1] == 'black' and lancer.material{color = {0, 0, 0}} or nil"))
  local want = {
    dark = "lancer: warning: the scene has no light (no point, spot or directional " ..
           "light, no emissive shape, no ambient light): only the background shows\n",
    black = "lancer: warning: every pixel is black: the lights reach nothing the " ..
            "camera sees (check the camera, the lights' positions and intensities, " ..
            "and the colours)\n",
    lit = "",
  }
  -- Lua's warnings as each host shows them: stock lua5.4 only under -W,
  -- as lauxlib's "Lua warning: ..."; the lancer command always, as they are.
  local hosts = {
    {"lua5.4 " .. T.quote(script), nil},
    {"lua5.4 -W " .. T.quote(script), "Lua warning: "},
    {T.quote(T.lancer) .. " " .. T.quote(script), ""},
    {T.quote(T.lancer) .. " --check " .. T.quote(script), ""},
  }
  for _, host in ipairs(hosts) do
    local cmd, prefix = host[1], host[2]
    for kind, line in pairs(want) do
      local out, err, code = T.run(cmd .. " " .. kind)
      T.check_exit(code, 0, out, err)
      T.eq(out, "went on\n", cmd .. " " .. kind .. ": stdout")
      err = err:gsub("check: [^\n]*\n", ""):gsub("  %S+ %S+ +[^\n]*\n", "")
      local shown = (prefix and line ~= "") and prefix .. line or ""
      T.eq(err, shown, cmd .. " " .. kind .. ": stderr")
    end
  end
  os.remove(script)
end)
