-- test_accuracy.lua: `lancer --accuracy`, img:error and friends, lancer.plot.
local T = require "harness"
local lancer = require "lancer"

local q = T.quote
local temp_dir = T.temp_dir
local write = T.write

-- Rows of a CSV file as tables keyed by the header's names, and the header.
local function read_csv(path)
  local text = assert(T.slurp(path), "no file " .. path)
  local lines = {}
  for line in text:gmatch("[^\n]+") do lines[#lines + 1] = line end
  local head = {}
  for name in lines[1]:gmatch("[^,]+") do head[#head + 1] = name end
  local rows = {}
  for i = 2, #lines do
    local row, k = {}, 0
    for v in lines[i]:gmatch("[^,]+") do
      k = k + 1
      row[head[k]] = tonumber(v) or v
    end
    rows[#rows + 1] = row
  end
  return rows, head
end

-- Least-squares slope of log y against log x.
local function loglog_slope(xs, ys)
  local n, sx, sy, sxx, sxy = #xs, 0, 0, 0, 0
  for i = 1, n do
    local x, y = math.log(xs[i]), math.log(ys[i])
    sx, sy, sxx, sxy = sx + x, sy + y, sxx + x * x, sxy + x * y
  end
  return (n * sxy - sx * sy) / (n * sxx - sx * sx)
end

-- An image from rows of {r, g, b}.
local function image(rows)
  local img = lancer.image{width = #rows[1], height = #rows}
  for y, row in ipairs(rows) do
    for x, c in ipairs(row) do img:set(x, y, c[1], c[2], c[3]) end
  end
  return img
end

T.test("img:error: MSE, RMSE, relMSE, MAE and bias by hand", function()
  -- Differences 0.25, 0, -0.25 | 0.25, -0.5, 0.125 (all exact in float).
  local img = image{{{0.5, 0.25, 0}, {1, 0, 0.125}}}
  local ref = image{{{0.25, 0.25, 0.25}, {0.75, 0.5, 0}}}
  local e = img:error(ref)
  T.eq(e.mse, 0.453125 / 6, "mse")
  T.eq(e.rmse, math.sqrt(0.453125 / 6), "rmse")
  T.eq(e.mae, 1.375 / 6, "mae")
  T.eq(e.bias, -0.125 / 6, "bias")
  local rel = (0.0625 / 0.26 ^ 2 * 2 + 0.0625 / 0.76 ^ 2 + 0.25 / 0.51 ^ 2 +
               0.015625 / 0.01 ^ 2) / 6
  T.near(e.relmse, rel, 1e-12 * rel, "relmse")
  local z = ref:error(ref)
  T.eq(z.mse + z.relmse + z.mae + math.abs(z.bias), 0, "an image against itself")
  T.check_error(function() img:error(lancer.image{width = 1, height = 2}) end,
                "'error'", "2x1 and 1x2")
end)

T.test("img:add averages, lancer.image fills, img:set checks its pixel", function()
  local a = lancer.image{width = 2, height = 1, color = {1, 2, 3}}
  local b = image{{{3, 2, 1}, {0, 0, 0}}}
  T.eq(a:add(a, -0.5):add(b, 0.5), a, "add returns the image")
  local r, g, bl = a:pixel(1, 1)
  T.eq(r + g + bl, 6, "(0.5 + 1.5, 1 + 1, 1.5 + 0.5)")
  T.eq(r, 2, "red")
  T.eq(select(3, a:pixel(2, 1)), 1.5, "second pixel: half of 3")
  T.check_error(function() a:set(3, 1, 0, 0, 0) end, "test_accuracy.lua:", "'set'",
                "x must be in [1, 2], got 3")
  T.check_error(function() lancer.image{width = 2} end, "test_accuracy.lua:",
                "'image'", "field 'height'")
  T.check_error(function() a:add(b, 0 / 0) end, "'add'", "weight must be finite")
end)

-- A small scene whose pixel noise comes from the camera samples alone:
-- point lights, hard edges, a mirror.
local SCENE = [[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 0.5, 0}},
                       ambient = 0.1}
s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                   material = lancer.material{kr = 0.5}})
s:add(lancer.sphere{center = {0, 1, 0}, radius = 1,
                    material = lancer.material{kr = 0.6, color = {0.9, 0.4, 0.3}}})
s:add(lancer.box{min = {1.2, 0, -0.5}, max = {2, 0.8, 0.3}})
s:add(lancer.point_light{position = {2, 4, -2}, intensity = 20})
]]

T.test("--accuracy --knob samples: table, CSVs, n^-1/2 when random, plot", function()
  local dir = temp_dir()
  local script = dir .. "/tiny.lua"
  write(script, SCENE .. [[
local img = s:render{width = 24, height = 16, sampler = "random"}
print("script got " .. tostring(img))
]])
  local out, err, code = T.run(
    ("%s --accuracy --knob samples=2,8,32 --seeds 2 --out %s %s")
    :format(q(T.lancer), q(dir .. "/o"), q(script)))
  T.eq(code, 0, "exit status; stderr: " .. err)
  assert(out:find("render 1 of tiny at 24x16, knob samples, 2 seeds", 1, true), out)
  assert(out:find("reference: samples=512, 2 renders of 256 averaged", 1, true), out)
  assert(out:find("best value: samples=%d+"), out)
  assert(out:find("script got lancer.Image 24x16", 1, true),
         "the script goes on with the reference: " .. out)

  local rows, head = read_csv(dir .. "/o/tiny-samples.csv")
  T.eq(table.concat(head, ","), "knob,level,seeds,seconds,rays,rmse,rmse_min,rmse_max," ..
       "mse,relmse,mae,bias,efficiency", "summary columns")
  T.eq(#rows, 3, "one row per level")
  local levels, rmse = {}, {}
  for i, r in ipairs(rows) do
    levels[i], rmse[i] = r.level, r.rmse
    T.eq(r.knob, "samples", "knob")
    T.eq(r.seeds, 2, "seeds")
    assert(r.seconds > 0 and r.rays > 0, "time and rays are positive")
    assert(r.rmse_min <= r.rmse and r.rmse <= r.rmse_max, "mean within min-max")
    T.near(r.efficiency, 1 / (r.relmse * r.seconds), 1e-5 * r.efficiency, "efficiency")
    if i > 1 then assert(r.rmse < rows[i - 1].rmse, "RMSE falls with samples") end
  end
  T.eq(table.concat(levels, ","), "2,8,32", "levels")
  -- Independent samples: RMSE ~ n^-1/2. Jittered ones would fall faster
  -- (about n^-3/4 on edges), the same samples for every n not at all.
  local slope = loglog_slope(levels, rmse)
  assert(slope > -0.65 and slope < -0.35, "RMSE slope " .. slope .. " is not about -1/2")

  local runs = read_csv(dir .. "/o/tiny-samples-runs.csv")
  T.eq(#runs, 6, "3 levels x 2 seeds")
  for _, r in ipairs(runs) do
    T.eq(r.camera, 24 * 16 * r.level, "camera rays of samples=" .. r.level)
    T.eq(r.rays, r.camera + r.shadow + r.reflection + r.glossy + r.light,
         "rays: every kind but cut")
    assert(r.seconds > 0, "seconds")
  end

  local png = lancer.load_png(dir .. "/o/tiny-samples.png")
  T.eq(png.width .. "x" .. png.height, "720x450", "plot size")
  os.execute("rm -rf " .. q(dir))
end)

T.test("--accuracy --knob depth: bounces, every render, the scene restored", function()
  local dir = temp_dir()
  local script = dir .. "/mirror.lua"
  write(script, SCENE .. [[
s:render{width = 16, height = 12}
s:render{width = 16, height = 12}
print("max_depth after: " .. s.max_depth)
]])
  local out, err, code = T.run(("%s --accuracy --knob depth=0,1,2 --seeds 2 --out %s %s")
    :format(q(T.lancer), q(dir), q(script)))
  T.eq(code, 0, "exit status; stderr: " .. err)
  assert(out:find("reference: max_depth=64, 2 seeds averaged", 1, true), out)
  assert(out:find("max_depth after: 3", 1, true), "the depth is put back: " .. out)
  for _, name in ipairs{"mirror-max_depth", "mirror-2-max_depth"} do
    local rows = read_csv(dir .. "/" .. name .. ".csv")
    T.eq(#rows, 3, name .. " rows")
    -- One pixel-centre sample: no noise, the error is the truncation alone.
    assert(rows[1].rmse > rows[2].rmse and rows[2].rmse > rows[3].rmse,
           "error falls with depth")
    T.eq(rows[1].rmse_min, rows[1].rmse_max, "the same image for every seed")
  end
  local runs = read_csv(dir .. "/mirror-max_depth-runs.csv")
  T.eq(runs[1].level, 0, "first run at depth 0")
  T.eq(runs[1].reflection, 0, "depth 0 traces no reflection")
  assert(runs[3].reflection > 0, "depth 1 does")
  os.execute("rm -rf " .. q(dir))
end)

T.test("--accuracy: a knob the scene has no use for is said to change nothing", function()
  local dir = temp_dir()
  local script = dir .. "/plain.lua"
  write(script, SCENE .. "s:render{width = 16, height = 12}\n")
  local out, err, code = T.run(
    ("%s --accuracy --knob cone_samples=1,4 --seeds 2 --out %s %s")
    :format(q(T.lancer), q(dir), q(script)))
  T.eq(code, 0, "exit status; stderr: " .. err)
  assert(out:find("nothing in this scene uses cone_samples", 1, true), out)
  local rows = read_csv(dir .. "/plain-cone_samples-runs.csv")
  T.eq(rows[1].glossy + rows[3].glossy, 0, "no glossy rays at either level")
  os.execute("rm -rf " .. q(dir))
end)

T.test("--accuracy: bad options exit 2 naming the flag, before any render", function()
  local dir = temp_dir()
  local script = dir .. "/s.lua"
  write(script, "error('the script ran')\n")
  local cases = {
    {"--accuracy --knob sample=1,2", "unknown knob 'sample'"},
    {"--accuracy --knob samples=", "no levels for samples"},
    {"--accuracy --knob samples=1,x", "samples level 'x' is not an integer"},
    {"--accuracy --knob samples=4,2", "levels must increase, got 2 after 4"},
    {"--accuracy --knob samples=0,2", "levels must be in [1, "},
    {"--accuracy --knob cone_samples=1,8192", "levels must be in [1, 4096], got 8192"},
    {"--accuracy --knob noise=0.1,0.2", "noise levels must decrease, got 0.2 after 0.1"},
    {"--accuracy --knob noise=0.2,0", "noise levels must be in (0, 1], got 0"},
    {"--accuracy --knob noise=0.2,x", "noise level 'x' is not a number"},
    {"--accuracy --knob indirect=2,1", "indirect levels must increase, got 1 after 2"},
    {"--accuracy --knob samples", "'--knob' needs NAME=L1,L2,..., got 'samples'"},
    {"--accuracy --knob samples=1,2 --seeds 1", "'--seeds' needs at least 2 seeds"},
    {"--knob samples=1,2", "'--knob' needs --accuracy"},
    {"--seeds 4", "'--seeds' needs --accuracy"},
    {"--accuracy", "'--accuracy' needs --knob"},
    {"--accuracy --check --knob samples=1,2", "'--accuracy' cannot go with --check"},
  }
  for _, c in ipairs(cases) do
    local out, err, code = T.run(("%s %s %s"):format(q(T.lancer), c[1], q(script)))
    T.eq(code, 2, c[1] .. ": exit status; stderr: " .. err)
    assert(err:find(c[2], 1, true), ("%s: %q not in %s"):format(c[1], c[2], err))
    assert(not err:find("\n.", 1), c[1] .. ": one line: " .. err)
    T.eq(out, "", c[1] .. ": stdout")
  end
  local _, err, code = T.run(q(T.lancer) .. " --accuracy --knob samples=1,2")
  T.eq(code, 2, "no script")
  assert(err:find("'--accuracy' needs a script", 1, true), err)
  write(script, "print('no render')\n")
  _, err, code = T.run(("%s --accuracy --knob samples=1,2 %s"):format(q(T.lancer),
                                                                    q(script)))
  T.eq(code, 1, "a script that renders nothing")
  assert(err:find("rendered nothing", 1, true), err)
  os.execute("rm -rf " .. q(dir))
end)

T.test("lancer.plot: points, the line through them, the axes where mapped", function()
  local plot = require "lancer.plot"
  local pts = {{x = 0.002, y = 0.1, label = "1"}, {x = 0.02, y = 0.03, label = "10"},
               {x = 0.2, y = 0.01, label = "100"}}
  local cv, frame = plot.draw{points = pts, title = "test", xlabel = "seconds",
                              ylabel = "rmse", slopes = {{-0.5, "slope -1/2"}}}
  T.eq(cv.img.width .. "x" .. cv.img.height, plot.WIDTH .. "x" .. plot.HEIGHT, "size")
  local function blue(x, y)
    local r, g, b = cv.img:pixel(math.floor(x + 0.5) + 1, math.floor(y + 0.5) + 1)
    return b > 0.5 and r < 0.1
  end
  -- Decades 1e-3..1 by 1e-2..1e-1: x = 0.002 sits log10(2)/3 of the way across.
  local x1, y1 = frame.map(0.002, 0.1)
  T.near(x1, 96 + math.log(2, 10) / 3 * (plot.WIDTH - 1 - 36 - 96), 1e-9, "x mapping")
  T.eq(y1, 40, "y = 0.1 at the top of decades 1e-2..1e-1")
  for i, p in ipairs(pts) do
    local x, y = frame.map(p.x, p.y)
    assert(blue(x, y), "marker " .. i)
    if i > 1 then
      local ax, ay = frame.map(pts[i - 1].x, pts[i - 1].y)
      for t = 0.25, 0.75, 0.25 do
        assert(blue(ax + (x - ax) * t, ay + (y - ay) * t), "line into point " .. i)
      end
    end
  end
  -- The frame's bottom-left corner is black; a spot far from everything white.
  T.eq(select(1, cv.img:pixel(96 + 1, plot.HEIGHT - 64)), 0, "axis corner")
  local cx, cy = frame.map(0.0012, 0.012)
  T.eq(select(1, cv.img:pixel(math.floor(cx), math.floor(cy))), 1, "empty area")
  local dir = temp_dir()
  T.eq(plot.loglog{path = dir .. "/p.png", points = pts, own = true}, "own plot", "how")
  T.eq(lancer.load_png(dir .. "/p.png").width, plot.WIDTH, "saved")
  os.execute("rm -rf " .. q(dir))
end)
