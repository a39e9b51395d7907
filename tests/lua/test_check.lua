-- test_check.lua: `lancer --check` and scene:transformed, which it uses.
local T = require "harness"
local lancer = require "lancer"

local function script(text)
  local path = os.tmpname() .. ".lua"
  local f = assert(io.open(path, "w"))
  f:write(text)
  f:close()
  return path
end

local STABLE = [[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 0.5, 0}},
                       ambient = 0.1}
s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}})
s:add(lancer.sphere{center = {0, 1, 0}, radius = 1, material = lancer.material{kr = 0.4}})
s:add(lancer.box{min = {1.2, 0, -0.5}, max = {2, 0.8, 0.3}})
s:add(lancer.triangle{a = {-2, 0, 1}, b = {-1, 2, 1}, c = {-3, 1.5, 1}})
s:add(lancer.point_light{position = {2, 4, -2}, intensity = 20})
s:render{width = 640, height = 480}
s:render{width = 64, height = 64}
]]

T.test("--check: a sound scene is stable at every scale and far away", function()
  local path = script(STABLE)
  local out, err, code = T.run(T.lancer .. " --check " .. path)
  os.remove(path)
  T.eq(code, 0, "exit status; stderr: " .. err)
  assert(err:find("render 1 at 128x96", 1, true), "the first render is made small: " .. err)
  assert(err:find("render 2 at 64x64", 1, true), "each render is checked: " .. err)
  local n = 0
  for pct in err:gmatch("(%d+%.%d+) %% of pixels within 1/255") do
    assert(tonumber(pct) >= 99.9, "a variant differs: " .. err)
    n = n + 1
  end
  T.eq(n, 6, "three variants for each of two renders")
  assert(err:find("0 of 2 renders unstable", 1, true), err)
end)

T.test("--check: a scene whose scaled copy leaves the coordinate range is unstable, exit 3",
       function()
  local path = script([[
local lancer = require "lancer"
local K = 1e28
local s = lancer.scene{camera = lancer.camera{from = {0, 0, -4 * K}, at = {0, 0, 0}}}
s:add(lancer.sphere{center = {0, 0, 0}, radius = K})
s:add(lancer.point_light{position = {K, 2 * K, -3 * K}, intensity = 10 * K * K})
s:render{width = 64, height = 48}
]])
  local _, err, code = T.run(T.lancer .. " --check " .. path)
  os.remove(path)
  T.eq(code, 3, "exit status; stderr: " .. err)
  assert(err:find("UNSTABLE", 1, true) and err:find("1 of 1 renders unstable", 1, true), err)
end)

T.test("--check: a script that renders nothing, or fails, is not called stable", function()
  local path = script("print('no render')\n")
  local _, err, code = T.run(T.lancer .. " --check " .. path)
  os.remove(path)
  T.eq(code, 3, "nothing checked")
  assert(err:find("rendered nothing", 1, true), err)
  path = script("error('boom')\n")
  _, err, code = T.run(T.lancer .. " --check " .. path)
  os.remove(path)
  T.eq(code, 1, "a script error is a script error")
end)

T.test("--check and --accuracy never write the images the script saves", function()
  local dir = T.temp_dir()
  local path = dir .. "/s.lua"
  local f = assert(io.open(path, "w"))
  f:write((STABLE:gsub("s:render{width = 64, height = 64}\n$",
    "s:render{width = 64, height = 64}:save(arg[1])\n" ..
    "lancer.image{width = 2, height = 2}:save(arg[2])\n")))
  f:close()
  local final, fresh = dir .. "/final.png", dir .. "/fresh.png"
  for _, opts in ipairs{"--check", "--accuracy --knob samples=1,2 --seeds 2 --out " ..
                                   T.quote(dir .. "/acc")} do
    T.write(final, "the user's own picture")
    local _, err, code = T.run(("%s %s %s %s %s"):format(T.lancer, opts, T.quote(path),
                                                         T.quote(final), T.quote(fresh)))
    T.eq(code, 0, opts .. ": exit status; stderr: " .. err)
    T.eq(T.slurp(final), "the user's own picture", opts .. ": final.png overwritten")
    T.eq(T.slurp(fresh), nil, opts .. ": fresh.png written")
    local tool = opts:match("^%-%-(%a+)")
    assert(err:find(tool .. ": not writing " .. final, 1, true), err)
  end
  assert(T.slurp(dir .. "/acc/s-2-samples.png"), "--accuracy's own plot not written")
  os.execute("rm -rf " .. T.quote(dir))
end)

T.test("scene:transformed moves the camera, scales sizes and light intensity", function()
  local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 0.5, 0}}}
  s:add(lancer.sphere{center = {0, 1, 0}, radius = 1})
  s:add(lancer.point_light{position = {2, 4, -2}, intensity = 20})
  local t = s:transformed(10, {1, 2, 3})
  T.eq(t.camera.from[2], 12, "camera moved")
  T.eq(select(1, t:count()), 1, "one shape")
  local a = s:render{width = 32, height = 24}
  local b = t:render{width = 32, height = 24}
  T.eq(a:diff(b, 1 / 255).within, 1, "same picture")
  T.check_error(function() s:transformed(0) end, "test_check.lua:", "'transformed'",
                "field 'scale'", "> 0")
end)
