-- test_bench_glass.lua: the bench's glass-and-checker scene as the peer
-- writers put it (tools/bench/povray.lua, tachyon.lua), and, where POV-Ray is
-- installed, its image against lancer's scenes/bench/glass.lua at a small size.
local T = require "harness"
local lancer = require "lancer"

local scenes = dofile("tools/bench/scenes.lua")
local povray = dofile("tools/bench/povray.lua")
local tachyon = dofile("tools/bench/tachyon.lua")

local function tmpdir()
  local dir = os.tmpname()
  os.remove(dir)
  assert(os.execute("mkdir -p " .. T.quote(dir)))
  return dir
end

local function has(text, part)
  assert(text:find(part, 1, true), ("%q not in:\n%s"):format(part, text))
end

T.test("povray.lua writes the glass as the fixed model, with its interior", function()
  local tex = povray.texture(scenes.glass().materials.glass)
  has(tex, "pigment { rgbt <1, 1, 1, 0.9> }")
  has(tex, "finish { ambient 0 diffuse 0 reflection { 0.1 } }")
  has(tex, "interior { ior 1.5 }")
  assert(not tex:find("fresnel") and not tex:find("conserve_energy"), tex)
end)

T.test("povray.lua writes the checker as a checker pigment, unmoved", function()
  local tex = povray.texture(scenes.glass().materials.floor)
  has(tex, "pigment { checker rgb <0.95, 0.85, 0.1>, rgb <0.9, 0.1, 0.05> scale 1 }")
  assert(not tex:find("translate"), tex)
end)

T.test("povray.lua refuses glass whose kr + kt is not 1", function()
  local m = scenes.glass().materials.glass
  m.kr = 0.2
  local ok, msg = pcall(povray.texture, m)
  assert(not ok, "no error raised")
  has(msg, "kr + kt = 1")
end)

T.test("the glass scene's file: 5 bounces are max_trace_level 6", function()
  local dir = tmpdir()
  local path = dir .. "/glass.pov"
  povray.write(scenes.glass(), path, scenes.grid_vertex)
  local text = T.slurp(path)
  os.execute("rm -rf " .. T.quote(dir))
  has(text, "max_trace_level 6 adc_bailout 0")
  has(text, "plane { <0, 1, 0>, -0.5 ")
  local _, spheres = text:gsub("\nsphere {", "")
  T.eq(spheres, 2, "spheres")
end)

T.test("tachyon.lua refuses the glass scene (no refraction)", function()
  local dir = tmpdir()
  local ok, msg = pcall(tachyon.write, scenes.glass(), dir .. "/glass.dat",
                        scenes.grid_vertex)
  os.execute("rm -rf " .. T.quote(dir))
  assert(not ok, "no error raised")
  has(msg, "material '")
end)

-- The bench's image check at 160x90: the same thresholds (report.lua).
T.test("glass scene: lancer's image is POV-Ray's at 160x90", function()
  if not os.execute("command -v povray > /dev/null 2>&1") then
    T.skip("povray not installed")
  end
  local report = dofile("tools/bench/report.lua")
  local scene = scenes.glass()
  scene.width, scene.height = 160, 90
  local dir = tmpdir()
  povray.write(scene, dir .. "/glass.pov", scenes.grid_vertex)
  local words = {}
  for i, w in ipairs(povray.command(scene, "glass.pov", "glass.png", 1, 1)) do
    words[i] = T.quote(w)
  end
  assert(os.execute(("cd %s && %s > /dev/null 2>&1"):format(T.quote(dir),
                                                           table.concat(words, " "))))
  local pov = lancer.load_png(dir .. "/glass.png", {encoding = "linear"})
  os.execute("rm -rf " .. T.quote(dir))
  local mine
  T.run_script("scenes/bench/glass.lua", {[0] = "scenes/bench/glass.lua", "1"}, nil,
               {width = 160, height = 90, samples = 1}, function(img) mine = img end)
  -- through the PNG's 8 bits, as the bench compares
  local tmp = os.tmpname() .. ".png"
  mine:save(tmp, {encoding = "linear"})
  mine = lancer.load_png(tmp, {encoding = "linear"})
  os.remove(tmp)
  local d = mine:diff(pov, report.IMAGE_TOL)
  assert(d.mean * 255 <= report.IMAGE_MEAN_MAX and d.within * 100 >= report.IMAGE_WITHIN_MIN,
         ("mean %.3f/255, %.2f %% within; worst pixel %d,%d off by %.0f/255"):format(
           d.mean * 255, d.within * 100, d.worst_x, d.worst_y, d.max * 255))
end)
