-- test_progressive.lua: render{progressive, on_pass}: the passes, the final
-- image equal to a plain render's bit for bit, stopping, errors in on_pass,
-- bad options; the command's --progress=lines.
local T = require "harness"
local lancer = require "lancer"

-- A room with a mirror ball, a glossy floor, an area light and a lens: every
-- sampled dimension (pixel, lens, cone, light) and, with indirect, paths.
local function scene()
  local s = lancer.scene{camera = lancer.camera{from = {0, 1.2, -4}, at = {0, 0.8, 0},
                                                aperture = 0.05, focus = 4}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                     material = lancer.material{color = 0.7, kr = 0.3, glossiness = 8}})
  s:add(lancer.sphere{center = {-0.6, 0.7, 0}, radius = 0.7,
                      material = lancer.material{color = {0.9, 0.3, 0.2}, ks = 0.4}})
  s:add(lancer.sphere{center = {0.9, 0.5, 0.4}, radius = 0.5,
                      material = lancer.material{color = 0.9, kr = 0.8}})
  s:add(lancer.sphere{center = {0, 3, -1}, radius = 0.3,
                      material = lancer.material{color = 1, emission = 6}})
  s:add(lancer.point_light{position = {2, 4, -3}, intensity = 30})
  return s
end

-- Every channel's bits, alpha included.
local function digest(img)
  local h = -3750763034362895579
  for y = 1, img.height do
    for x = 1, img.width do
      local r, g, b, a = img:pixel(x, y)
      local s = string.pack("<ffff", r, g, b, a or -1)
      for i = 1, #s do h = (h ~ s:byte(i)) * 1099511628211 end
    end
  end
  return ("%016x"):format(h)
end

local CASES = {
  {name = "plain", samples = 10},
  {name = "one sample", samples = 1},
  {name = "noise", samples = 32, noise = 0.05, min_samples = 4},
  {name = "noise, odd min_samples", samples = 24, noise = 0.02, min_samples = 5},
  {name = "alpha", samples = 6, alpha = true},
  {name = "alpha and noise", samples = 16, noise = 0.05, min_samples = 2, alpha = true},
  {name = "region", samples = 7, region = {5, 3, 27, 19}},
  {name = "region and noise", samples = 16, noise = 0.03, min_samples = 2,
   region = {9, 0, 32, 11}},
  {name = "indirect", samples = 6, indirect = 2},
  {name = "indirect, noise, alpha", samples = 8, indirect = 3, noise = 0.05,
   min_samples = 2, alpha = true},
  {name = "jitter sampler", samples = 9, sampler = "jitter"},
}

for _, c in ipairs(CASES) do
  T.test("progressive: the final image is the plain render's, bit for bit: " .. c.name,
    function()
      local s = scene()
      local o = {width = 32, height = 24, progress = false}
      for k, v in pairs(c) do if k ~= "name" then o[k] = v end end
      local plain, ps = s:render(o)
      for _, threads in ipairs{1, 2, 3} do
        o.threads, o.progressive = threads, true
        local seen = {}
        o.on_pass = function(img, pass, st)
          T.eq(pass, #seen + 1, "pass number")
          T.eq(st.passes, pass, "stats.passes in on_pass")
          seen[pass] = {img = img, samples = st.samples}
        end
        local img, st = s:render(o)
        T.eq(digest(img), digest(plain), ("digest at %d threads"):format(threads))
        T.eq(st.samples, ps.samples, "samples")
        T.eq(st.rays.camera, ps.rays.camera, "camera rays")
        T.eq(st.converged, ps.converged, "converged pixels")
        T.eq(st.stopped, false, "stopped")
        T.eq(#seen, st.passes, "on_pass calls")
        T.eq(digest(seen[#seen].img), digest(plain), "the last pass's image")
        T.eq(seen[#seen].samples, st.samples, "the last pass's samples")
        if not c.noise then
          -- 1, 2, 4, ... then the rest: each pixel takes that many, in all.
          local n, k = 1, 0
          local pixels = img.width * img.height
          while true do
            k = k + 1
            T.eq(seen[k].samples, n * pixels, ("samples after pass %d"):format(k))
            if n == c.samples then break end
            n = math.min(2 * n, c.samples)
          end
          T.eq(k, st.passes, "passes")
        end
      end
    end)
end

T.test("progressive: pass k's image is a plain render of 2^(k-1) of N's samples", function()
  -- With N = 1, 2, 4 the passes' prefixes are whole renders' samples only
  -- when N is the same: sample s of N is point s of an N-point set, so the
  -- second pass of an 8-sample render is the mean of points 0, 1 of 8.
  -- Checked against a render that stops there.
  local s = scene()
  local o = {width = 24, height = 16, samples = 8, progressive = true, progress = false}
  local second
  o.on_pass = function(img, pass) if pass == 2 then second = digest(img) end end
  s:render(o)
  o.on_pass = function(_, pass) return pass < 2 end
  local img, st = s:render(o)
  T.eq(st.stopped, true, "stopped")
  T.eq(st.passes, 2, "passes")
  T.eq(st.samples, 2 * 24 * 16, "samples")
  T.eq(digest(img), second, "the image returned is the stopped pass's")
  -- Within the pass, each pixel is the mean of its 2 samples: under a flat
  -- background every sample is the same, so the mean is exact.
  local flat = lancer.scene{camera = lancer.camera{from = {0, 0, -1}, at = {0, 0, 0}},
                            background = {0.25, 0.5, 0.125}, ambient = 0.1}
  local f = flat:render{width = 4, height = 4, samples = 8, progressive = true,
                        progress = false, on_pass = function() return false end}
  T.eq(select(2, f:pixel(3, 3)), 0.5, "a flat pixel after pass 1")
end)

T.test("progressive: returning false on the last pass is not a stop", function()
  local s = scene()
  local img, st = s:render{width = 8, height = 8, samples = 4, progressive = true,
                           progress = false, on_pass = function(_, pass) return pass < 3 end}
  T.eq(st.passes, 3, "passes")
  T.eq(st.stopped, false, "stopped")
  local plain = s:render{width = 8, height = 8, samples = 4, progress = false}
  T.eq(digest(img), digest(plain), "digest")
end)

T.test("progressive: a plain render reports one pass; on_pass images are copies", function()
  local s = scene()
  local _, st = s:render{width = 8, height = 8, samples = 4, progress = false}
  T.eq(st.passes, 1, "passes")
  T.eq(st.stopped, false, "stopped")
  local kept = {}
  s:render{width = 8, height = 8, samples = 4, progressive = true, progress = false,
           on_pass = function(img) kept[#kept + 1] = img end}
  T.eq(#kept, 3, "passes seen")
  assert(digest(kept[1]) ~= digest(kept[3]), "pass 1's copy changed with later passes")
end)

T.test("progressive: an error in on_pass ends the render with that error", function()
  local s = scene()
  local calls = 0
  T.check_error(function()
    s:render{width = 16, height = 16, samples = 8, progressive = true, progress = false,
             on_pass = function(_, pass)
               calls = calls + 1
               if pass == 2 then error("stop here") end
             end}
  end, "test_progressive.lua:", "stop here")
  T.eq(calls, 2, "on_pass calls")
  -- An error object other than a string comes through as itself.
  local marker = {}
  local ok, e = pcall(s.render, s, {width = 8, height = 8, samples = 2, progressive = true,
                      progress = false, on_pass = function() error(marker) end})
  assert(not ok and e == marker, "the error object changed: " .. tostring(e))
  -- The scene renders on afterwards: nothing was left locked.
  local img = s:render{width = 8, height = 8, progress = false}
  T.eq(img.width, 8, "a render after the error")
  T.check_error(function()
    s:render{width = 8, height = 8, samples = 2, progressive = true, progress = false,
             on_pass = function() return 0 end}
  end, "test_progressive.lua:", "'render'", "field 'on_pass'", "returned number",
    "false stops the render")
end)

T.test("progressive: on_pass cannot touch the scene it renders", function()
  local s = scene()
  local m = lancer.mesh{}
  m:add_vertices{0, 0, 0, 1, 0, 0, 0, 1, 0}
  m:add_faces{1, 2, 3}
  s:add(m)
  local other = lancer.scene{camera = lancer.camera{from = {0, 0, -3}, at = {0, 0, 0}}}
  other:add(lancer.sphere{center = {0, 0, 0}, radius = 1},
            lancer.point_light{position = {0, 2, -3}, intensity = 10})
  local function during(f, ...)
    return T.check_error(function()
      s:render{width = 8, height = 8, samples = 2, progressive = true, progress = false,
               on_pass = f}
    end, "test_progressive.lua:", ...)
  end
  local busy = "lancer.Scene is rendering: its render's on_pass cannot"
  during(function() s:add(lancer.sphere{center = {0, 0, 0}, radius = 1}) end, busy)
  during(function() s:add(lancer.point_light{position = {0, 1, 0}}) end, busy)
  during(function() s:render{width = 4, height = 4} end, busy)
  during(function() s:objects() end, busy)
  during(function() m:add_vertices{0, 0, 1} end, "add_vertices: no mesh may grow")
  during(function() local closing <close> = s end, busy, "close it")
  T.eq(#s:objects(), 6, "objects after the refused changes: the scene's 5 and the mesh")
  -- Another scene renders inside on_pass, and the outer render goes on.
  local inner = 0
  local _, st = s:render{width = 8, height = 8, samples = 2, progressive = true,
                         progress = false, on_pass = function()
                           inner = inner + other:render{width = 4, height = 4,
                                                        progress = false}.width
                         end}
  T.eq(inner, 8, "inner renders' widths")
  T.eq(st.passes, 2, "outer passes")
  m:add_vertices{0, 0, 1}                       -- allowed again afterwards
end)

T.test("progressive: bad options name the field", function()
  local s = scene()
  T.check_error(function() s:render{progressive = 1} end,
                "test_progressive.lua:", "'render'", "field 'progressive'", "boolean expected")
  T.check_error(function() s:render{progressive = true, on_pass = "draw"} end,
                "test_progressive.lua:", "'render'", "field 'on_pass'",
                "function expected, got string")
  T.check_error(function() s:render{on_pass = function() end} end,
                "test_progressive.lua:", "'render'", "field 'on_pass'",
                "set progressive = true too")
  T.check_error(function() s:render{progress = "dots"} end,
                "test_progressive.lua:", "'render'", "field 'progress'",
                "true, false or 'lines' expected, got 'dots'")
  T.check_error(function() s:render{progressive = true, aovs = {"depth"}} end,
                "test_progressive.lua:", "'render'", "field 'aovs'",
                "not made by a progressive render")
  T.check_error(function() s:render{progressiv = true} end,
                "test_progressive.lua:", "unknown field 'progressiv'",
                "did you mean 'progressive'")
end)

-- ---- The command line ----------------------------------------------------------

local function lines_of(text, pattern)
  local t = {}
  for l in text:gmatch("[^\n]+") do
    local n, m = l:match(pattern)
    if n then t[#t + 1] = {tonumber(n), tonumber(m)} end
  end
  return t
end

T.test("--progress=lines: 'progress N/100' lines on stderr, rising to 100", function()
  local dir = T.temp_dir()
  local script = dir .. "/s.lua"
  T.write(script, [[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 0, -4}, at = {0, 0, 0}}}
s:add(lancer.sphere{center = {0, 0, 0}, radius = 1},
      lancer.point_light{position = {2, 4, -3}, intensity = 25})
s:render{width = 256, height = 256, samples = 16, noise = 0.01, min_samples = 2}
s:render{width = 64, height = 64, progress = true}
assert(s:explain{x = 5, y = 5, width = 10, height = 10})   -- explain has no progress
]])
  for _, form in ipairs{"--progress=lines", "--progress lines"} do
    local out, err, code = T.run(("%s %s %s"):format(T.lancer, form, T.quote(script)))
    T.check_exit(code, 0, out, err)
    local got = lines_of(err, "^progress (%d+)/(%d+)$")
    -- Every line is one: nothing else on stderr.
    local _, all = err:gsub("\n", "")
    T.eq(#got, all, "lines on stderr that are progress lines")
    -- Two renders: each from 0/100 up to 100/100, strictly rising.
    local starts, last = 0, -1
    for _, p in ipairs(got) do
      T.eq(p[2], 100, "M")
      if p[1] == 0 then
        T.eq(last, starts == 0 and -1 or 100, "the render before ended at 100")
        starts = starts + 1
      else
        assert(p[1] > last, ("progress went from %d to %d"):format(last, p[1]))
      end
      last = p[1]
    end
    T.eq(starts, 2, "renders")
    T.eq(last, 100, "the last line")
    assert(#got >= 4 and #got <= 202, "lines: " .. #got)
  end
  local _, err, code = T.run(("%s --progress=dots %s"):format(T.lancer, T.quote(script)))
  T.check_exit(code, 2, "", err)
  T.has(err, "option '--progress' needs bar, lines or none, got 'dots'")
  local _, err2 = T.run(("%s --progress=none %s"):format(T.lancer, T.quote(script)))
  T.eq(err2, "", "stderr with --progress=none")
  os.execute("rm -rf " .. T.quote(dir))
end)
