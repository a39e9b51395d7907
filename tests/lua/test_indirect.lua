-- test_indirect.lua: light that bounces (render option indirect), against
-- closed forms and cross-checks (issue 14 item 5): the furnace Le/(1 - rho)
-- and its truncated series, white furnaces per material, a convex object
-- and a plane under a uniform sky reading rho L, direct light equal to
-- Whitted's, BSDF sampling alone against NEE + MIS and roulette against
-- none within k sigma measured from seeds, determinism; ambient occlusion,
-- .hdr skies, and the options' errors.
local T = require "harness"
local lancer = require "lancer"

local HERE = "test_indirect.lua:"

local function mean(img)
  local s, n = 0, 0
  for y = 1, img.height do
    for x = 1, img.width do
      local r, g, b = img:pixel(x, y)
      s, n = s + r + g + b, n + 3
    end
  end
  return s / n
end

-- The furnace: the camera inside a closed sphere of albedo rho that emits Le.
local function furnace(rho, Le)
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, 0}, at = {0.3, 0.2, 1}}}
  s:add(lancer.sphere{center = {0, 0, 0}, radius = 5,
                      material = lancer.material{color = rho, kd = 1, emission = Le}})
  return s
end

T.test("furnace: indirect = N reads Le (1 + rho + ... + rho^(N+1)), every pixel", function()
  local rho, Le = 0.6, 0.3
  local s = furnace(rho, Le)
  for _, N in ipairs{1, 2, 3, 5} do
    local img, st = s:render{width = 8, height = 6, samples = 4, indirect = N,
                             roulette = false}
    local want = 0
    for k = 0, N + 1 do want = want + Le * rho ^ k end
    -- Every path sees the same: no noise, only float rounding.
    for y = 1, 6 do
      for x = 1, 8 do T.near(img:pixel(x, y), want, 1e-6, ("N %d at %d,%d"):format(N, x, y)) end
    end
    -- N bounces lit by NEE, and one more ray to see what the last meets.
    T.eq(st.rays.indirect, 8 * 6 * 4 * (N + 1), "one indirect ray per bounce")
  end
end)

T.test("furnace: with roulette, the limit Le / (1 - rho) within 4 sigma of the seeds", function()
  local rho, Le = 0.7, 0.3
  local s = furnace(rho, Le)
  local ms = {}
  for seed = 1, 6 do
    ms[seed] = mean(s:render{width = 16, height = 12, samples = 16, indirect = 200,
                             seed = seed})
  end
  local m, v = 0, 0
  for _, x in ipairs(ms) do m = m + x / #ms end
  for _, x in ipairs(ms) do v = v + (x - m) ^ 2 / (#ms - 1) end
  local sigma = math.sqrt(v / #ms)
  local want = Le / (1 - rho)
  -- 200 bounces leave 0.7^201 of it: nothing.
  assert(math.abs(m - want) <= 4 * sigma + 1e-6,
         ("mean %.6f, want %.6f, sigma %.2e"):format(m, want, sigma))
  assert(sigma > 0 and sigma < 0.01, "noise measured: " .. sigma)
end)

-- A sphere of material m in front of the camera under a uniform sky L = 1.
local function under_sky(m, extra)
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, -3}, at = {0, 0, 0}, fov = 30},
                         background = 1, max_depth = 64}
  s:add(lancer.sphere{center = {0, 0, 0}, radius = 1, material = m})
  return s
end

T.test("white furnace per material: <= 1, and = 1 when lossless (BSDF sampling)", function()
  local cases = {
    {"diffuse kd 0.6", lancer.material{kd = 0.6}, 0.6, 1e-6},
    {"lambert white", lancer.material{kd = 1}, 1, 1e-6},
    {"mirror kr 1", lancer.material{kd = 0, kr = 1}, 1, 1e-6},
    {"kd 0.7 + kr 0.3", lancer.material{kd = 0.7, kr = 0.3}, 1, 1e-6},
    {"kd 1 + kr 1 scaled to 1", lancer.material{kd = 1, kr = 1}, 1, 1e-6},
    {"coloured", lancer.material{color = {0.5, 0.25, 1}, kd = 1}, (0.5 + 0.25 + 1) / 3, 1e-6},
  }
  for _, c in ipairs(cases) do
    local img = under_sky(c[2]):render{width = 12, height = 12, indirect = 1, nee = false}
    -- Only the sphere's pixels (the corners see the sky itself, 1).
    for y = 4, 9 do
      for x = 4, 9 do
        local r, g, b = img:pixel(x, y)
        T.near((r + g + b) / 3, c[3], c[4], c[1] .. (" at %d,%d"):format(x, y))
      end
    end
  end
  -- A highlight lobe loses what falls under the surface: <= 1, most of it kept.
  local phong = under_sky(lancer.material{kd = 0.5, ks = 0.5, alpha = 20})
  local img = phong:render{width = 12, height = 12, samples = 64, indirect = 1, nee = false}
  local pm = 0
  for y = 4, 9 do
    for x = 4, 9 do
      local r = img:pixel(x, y)
      pm = pm + r / 36
      assert(r < 1.02 and r > 0.7, ("phong at %d,%d: %g"):format(x, y, r))
    end
  end
  assert(pm <= 1.002, "phong furnace: " .. pm)
  -- Glass: lossless, so 1 but for the paths max_depth cuts (a few in 64).
  local glass = under_sky(lancer.material{kd = 0, kt = 1, ior = 1.5})
  local g = glass:render{width = 12, height = 12, samples = 16, indirect = 1, roulette = false}
  local m = 0
  for y = 4, 9 do for x = 4, 9 do m = m + g:pixel(x, y) / 36 end end
  assert(m <= 1 + 1e-6 and m > 0.99, "glass furnace: " .. m)
end)

T.test("a convex diffuse object and a plane under a uniform sky read rho L (NEE + MIS)",
function()
  for _, L in ipairs{1, 2.5} do
    local s = lancer.scene{camera = lancer.camera{from = {0, 0, -3}, at = {0, 0, 0}, fov = 30},
                           background = L}
    s:add(lancer.sphere{center = {0, 0, 0}, radius = 1, material = lancer.material{kd = 0.4}})
    local img = s:render{width = 8, height = 8, samples = 64, indirect = 2}
    local m = 0
    for y = 3, 6 do for x = 3, 6 do m = m + img:pixel(x, y) / 16 end end
    T.near(m, 0.4 * L, 0.01 * L, "sphere under sky " .. L)
  end
  local p = lancer.scene{camera = lancer.camera{from = {0, 3, 0}, at = {0, 0, 0.001}, fov = 60},
                         background = lancer.sky{zenith = 0.8, horizon = 0.8, ground = 0.8}}
  p:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}, material = lancer.material{kd = 0.5}})
  T.near(mean(p:render{width = 8, height = 8, samples = 64, indirect = 1}), 0.4, 0.004,
         "plane under a uniform sky texture")
end)

T.test("indirect = 1: the direct light of point, spot and sun lights is Whitted's", function()
  local s = lancer.scene{camera = lancer.camera{from = {0, 2, -4}, at = {0, 0.5, 0}}}
  local m = lancer.material{color = {0.8, 0.5, 0.3}, kd = 0.9}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}, material = m},
        lancer.point_light{position = {1, 3, -1}, intensity = 9},
        lancer.spot_light{position = {-1, 3, 0}, at = {0, 0, 0}, intensity = 9},
        lancer.directional_light{direction = {1, -1, 1}, irradiance = 1})
  local whitted = s:render{width = 32, height = 24}
  local path, st = s:render{width = 32, height = 24, indirect = 1}
  -- The bounce leaves for a black sky: the direct term alone, no noise.
  assert(path:diff(whitted).max <= 1e-6, "max " .. path:diff(whitted).max)
  T.eq(st.effects.indirect, true)
  T.eq(st.why.indirect, "indirect = 1: paths of up to 1 bounce, Russian roulette after " ..
       "3, lights sampled at each (MIS)")
  assert(st.rays.indirect > 0, "bounces traced")
end)

T.test("indirect = 1: an area light's direct light is Whitted's within noise", function()
  local s = lancer.scene{camera = lancer.camera{from = {0, 2, -4}, at = {0, 0.5, 0}}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                     material = lancer.material{color = {0.8, 0.5, 0.3}, kd = 0.9}},
        lancer.quad{corner = {-0.5, 2, -0.5}, u = {1, 0, 0}, v = {0, 0, 1},
                    material = lancer.material{kd = 0, emission = 5}},
        lancer.sphere{center = {1.5, 2, 0.5}, radius = 0.3,
                      material = lancer.material{kd = 0, emission = 5}})
  local ref = s:render{width = 16, height = 12, samples = 64, light_samples = 64}
  local e = s:render{width = 16, height = 12, samples = 64, indirect = 1}:error(ref)
  -- Measured: RMSE 2.5e-4 at this budget; bias far below it.
  assert(e.rmse < 2e-3 and math.abs(e.bias) < 2e-4, ("rmse %g bias %g"):format(e.rmse, e.bias))
end)

-- A small Cornell box: an area light under the ceiling, red and green walls.
local function cornell()
  local s = lancer.scene{camera = lancer.camera{from = {0, 1, -3.2}, at = {0, 1, 0}, fov = 45}}
  local function wall(corner, u, v, rgb)
    s:add(lancer.quad{corner = corner, u = u, v = v,
                      material = lancer.material{color = rgb, kd = 1}})
  end
  wall({-1, 0, -1}, {2, 0, 0}, {0, 0, 2}, 0.75)        -- floor
  wall({-1, 2, -1}, {2, 0, 0}, {0, 0, 2}, 0.75)        -- ceiling
  wall({-1, 0, 1}, {2, 0, 0}, {0, 2, 0}, 0.75)         -- back
  wall({-1, 0, -1}, {0, 0, 2}, {0, 2, 0}, {0.63, 0.07, 0.05})
  wall({1, 0, -1}, {0, 0, 2}, {0, 2, 0}, {0.14, 0.45, 0.09})
  s:add(lancer.box{min = {-0.5, 0, -0.2}, max = {0.1, 0.6, 0.4},
                   material = lancer.material{kd = 0.75}})
  s:add(lancer.quad{corner = {-0.25, 1.99, -0.25}, u = {0.5, 0, 0}, v = {0, 0, 0.5},
                    material = lancer.material{kd = 0, emission = 12}})
  return s
end

-- Per 4x4 block of an 16x16 image: the mean over seeds and its sigma.
local function block_stats(s, opts, seeds)
  local acc = {}
  for seed = 1, seeds do
    opts.seed = seed
    local img = s:render(opts)
    for by = 0, 3 do
      for bx = 0, 3 do
        local k, m = by * 4 + bx + 1, 0
        for y = 1, 4 do for x = 1, 4 do m = m + img:pixel(bx * 4 + x, by * 4 + y) / 16 end end
        acc[k] = acc[k] or {}
        acc[k][seed] = m
      end
    end
  end
  local out = {}
  for k, xs in ipairs(acc) do
    local m, v = 0, 0
    for _, x in ipairs(xs) do m = m + x / #xs end
    for _, x in ipairs(xs) do v = v + (x - m) ^ 2 / (#xs - 1) end
    out[k] = {mean = m, sigma = math.sqrt(v / #xs)}
  end
  return out
end

T.test("BSDF sampling alone and NEE + MIS converge to the same Cornell box (k sigma)",
function()
  local s = cornell()
  local a = block_stats(s, {width = 16, height = 16, samples = 64, indirect = 3}, 5)
  local b = block_stats(s, {width = 16, height = 16, samples = 64, indirect = 3, nee = false}, 5)
  local worse = 0
  for k = 1, 16 do
    local sig = math.sqrt(a[k].sigma ^ 2 + b[k].sigma ^ 2)
    assert(math.abs(a[k].mean - b[k].mean) <= 4.5 * sig + 1e-4,
           ("block %d: %.5f and %.5f, sigma %.2e"):format(k, a[k].mean, b[k].mean, sig))
    if b[k].sigma > a[k].sigma then worse = worse + 1 end
  end
  assert(worse >= 12, "BSDF sampling alone is the noisier in most blocks: " .. worse)
end)

T.test("Russian roulette does not bias the mean (with and without, k sigma)", function()
  local s = cornell()
  local a = block_stats(s, {width = 16, height = 16, samples = 32, indirect = 6}, 5)
  local b = block_stats(s, {width = 16, height = 16, samples = 32, indirect = 6,
                            roulette = false}, 5)
  for k = 1, 16 do
    local sig = math.sqrt(a[k].sigma ^ 2 + b[k].sigma ^ 2)
    assert(math.abs(a[k].mean - b[k].mean) <= 4.5 * sig + 1e-4,
           ("block %d: %.5f and %.5f, sigma %.2e"):format(k, a[k].mean, b[k].mean, sig))
  end
end)

T.test("paths are deterministic: threads, regions, and indirect = 0 is the seed's", function()
  local s = cornell()
  local o = {width = 24, height = 16, samples = 4, indirect = 3}
  o.threads = 1
  local one = s:render(o)
  o.threads = 2
  local two = s:render(o)
  T.eq(one:diff(two).max, 0, "1 and 2 threads")
  o.region = {8, 4, 20, 12}
  local part = s:render(o)
  for y = 1, 8 do
    for x = 1, 12 do
      local a = {part:pixel(x, y)}
      local b = {two:pixel(x + 8, y + 4)}
      for k = 1, 3 do T.eq(a[k], b[k], "region pixel") end
    end
  end
  local plain, st0 = s:render{width = 24, height = 16, samples = 4}
  local zero, st = s:render{width = 24, height = 16, samples = 4, indirect = 0}
  T.eq(plain:diff(zero).max, 0, "indirect = 0")
  T.eq(st.effects.indirect, false); T.eq(st.rays.indirect, 0)
  T.eq(st.why.indirect, "indirect = 0: direct light and mirrors (the seed's model)")
  local ledger = lancer.ledger(st)
  assert(ledger:find("off indirect  indirect = 0", 1, true), ledger)
  assert(ledger:find("indirect 0, ao 0", 1, true), ledger)
end)

T.test("explain shows a path's bounces and the sky as a light", function()
  local s = lancer.scene{camera = lancer.camera{from = {0, 1, -3}, at = {0, 0, 0}},
                         background = 0.5}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}})
  local kinds, sky = {}, false
  local function walk(n)
    kinds[n.kind] = true
    if n.light == "the sky" then sky = true end
    for _, c in ipairs(n.rays or {}) do walk(c) end
  end
  -- Half the sky's samples fall under the floor: a few pixels find one.
  for x = 1, 16 do
    local tree = s:explain{x = x, y = 12, width = 16, height = 16, indirect = 2}
    T.eq(tree.kind, "camera")
    walk(tree)
  end
  assert(kinds.indirect and kinds.light and sky, "bounces and sky rays recorded")
end)

-- ---- ambient occlusion ----------------------------------------------------------

T.test("ao: the ambient light times the share of probes that get away", function()
  local function scene(ceiling)
    local s = lancer.scene{camera = lancer.camera{from = {0, 0.5, 0}, at = {0, 0, 0.0001},
                                                  fov = 40}, ambient = 1}
    s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                       material = lancer.material{kd = 0, ka = 1}})
    if ceiling then
      s:add(lancer.plane{point = {0, 1, 0}, normal = {0, -1, 0},
                         material = lancer.material{kd = 0, ka = 0}})
    end
    return s
  end
  -- Open sky: every probe free, exactly the ambient light.
  local img, st = scene(false):render{width = 8, height = 8, ao = {samples = 16, distance = 5}}
  T.eq(mean(img), 1, "open floor"); T.eq(st.effects.ao, true)
  T.eq(st.rays.ao, 8 * 8 * 16, "probes counted")
  -- A ceiling at height 1 and probes of 10: free only when cos < 0.1, a
  -- share 0.1^2 = 0.01 of cosine-weighted directions.
  img = scene(true):render{width = 8, height = 8, samples = 16, ao = {samples = 64, distance = 10}}
  T.near(mean(img), 0.01, 0.002, "under a ceiling")
  -- Probes shorter than the gap: free again.
  img = scene(true):render{width = 8, height = 8, ao = {samples = 8, distance = 0.9}}
  T.eq(mean(img), 1, "short probes")
  -- No ambient light: nothing to darken, no probe.
  local s = scene(false)
  s.ambient = 0
  s:add(lancer.point_light{position = {0, 3, 0}, intensity = 9})
  local _, st2 = s:render{width = 4, height = 4, ao = {samples = 8, distance = 1}}
  T.eq(st2.effects.ao, false); T.eq(st2.rays.ao, 0)
  T.eq(st2.why.ao, "no ambient light to darken")
end)

-- ---- HDR skies -----------------------------------------------------------------

-- A w x h Radiance file of flat RGBE scanlines (as a file narrower than 8
-- pixels always is: src/image/hdr.c reads both kinds).
local function write_hdr(path, w, h, texel)
  local f = assert(io.open(path, "wb"))
  f:write(("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n"):format(h, w))
  for j = 1, h do for i = 1, w do f:write(string.char(table.unpack(texel(i, j)))) end end
  f:close()
end

T.test("load_hdr reads Radiance files; an .hdr sky lights a scene by importance", function()
  local path = os.tmpname() .. ".hdr"
  -- RGBE (128, 64, 32, 130) is (2, 1, 0.5); one bright texel, the rest dim.
  write_hdr(path, 4, 2, function(i, j)
    if i == 3 and j == 1 then return {128, 128, 128, 136} end   -- 128 each
    return {128, 64, 32, 130}
  end)
  local img = lancer.load_hdr(path)
  T.eq(img.width, 4); T.eq(img.height, 2)
  local r, g, b = img:pixel(1, 2)
  T.eq(r, 2); T.eq(g, 1); T.eq(b, 0.5)
  T.eq(img:pixel(3, 1), 128)
  local sky = lancer.image_texture{path = path, filter = "nearest"}
  os.remove(path)
  local s = lancer.scene{camera = lancer.camera{from = {0, 3, 0}, at = {0, 0, 0.001}, fov = 60},
                         background = sky}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}, material = lancer.material{kd = 0.5}})
  -- The floor sees the upper half only: the top row, (2, 1, 0.5) but for the
  -- bright texel. Importance sampling and BSDF sampling agree on the mean,
  -- and the importance-sampled one is the less noisy.
  -- Independent samples ('random'): the seeds' spread is then the noise.
  local a = block_stats(s, {width = 16, height = 16, samples = 16, indirect = 1,
                            sampler = "random"}, 6)
  local b = block_stats(s, {width = 16, height = 16, samples = 16, indirect = 1, nee = false,
                            sampler = "random"}, 6)
  local quieter = 0
  for k = 1, 16 do
    local sig = math.sqrt(a[k].sigma ^ 2 + b[k].sigma ^ 2)
    assert(math.abs(a[k].mean - b[k].mean) <= 4.5 * sig + 1e-3,
           ("block %d: %.4f and %.4f, sigma %.2e"):format(k, a[k].mean, b[k].mean, sig))
    if a[k].sigma < b[k].sigma then quieter = quieter + 1 end
  end
  assert(quieter >= 12, "importance sampling is the quieter in most blocks: " .. quieter)
end)

T.test("a filtered .hdr sky: light sampling covers the texels the filter spreads", function()
  -- A small sun (one texel of 4096, the rest 1) under bilinear filtering
  -- lights the texels around it too. Sampled by each texel's own
  -- luminance, those dim texels were rarely picked, and BSDF rays that met
  -- the sun's spread glow took nearly full MIS weight: fireflies, a spread
  -- 13 times the nearest texel's (measured: 2.05 against 0.152). Texels
  -- are now weighted by the filtered sky's mean over them (0.52: what is
  -- left is the filter's slope inside a texel, which a flat pdf misses).
  local path = os.tmpname() .. ".hdr"
  write_hdr(path, 32, 16, function(i, j)
    if i == 13 and j == 5 then return {128, 128, 128, 141} end   -- 4096 each
    return {128, 128, 128, 129}                                  -- 1
  end)
  local spread = {}
  for _, filter in ipairs{"nearest", "bilinear"} do
    local s = lancer.scene{camera = lancer.camera{from = {0, 3, 0}, at = {0, 0, 0.001},
                                                  fov = 60},
                           background = lancer.image_texture{path = path, filter = filter}}
    s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                       material = lancer.material{kd = 0.5}})
    -- Every pixel sees the same sky: the spread over pixels is the noise.
    local img = s:render{width = 32, height = 32, samples = 4, indirect = 1,
                         sampler = "random"}
    local m, v, n = 0, 0, img.width * img.height
    for y = 1, img.height do for x = 1, img.width do m = m + img:pixel(x, y) / n end end
    for y = 1, img.height do
      for x = 1, img.width do v = v + (img:pixel(x, y) - m) ^ 2 / (n - 1) end
    end
    spread[filter] = math.sqrt(v) / m
  end
  os.remove(path)
  assert(spread.bilinear <= 4 * spread.nearest,
         ("relative spread: bilinear %.3f, nearest %.3f"):format(spread.bilinear,
                                                                 spread.nearest))
end)

-- ---- errors --------------------------------------------------------------------

T.test("indirect, roulette, nee and ao raise naming the field", function()
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, -1}, at = {0, 0, 0}}}
  local C = T.check_error
  C(function() s:render{width = 4, height = 4, indirect = -1} end,
    HERE, "'render'", "indirect", "got -1")
  C(function() s:render{width = 4, height = 4, indirect = 1.5} end, HERE, "field 'indirect'")
  C(function() s:render{width = 4, height = 4, indirect = "lots"} end,
    HERE, "field 'indirect'", "got string")
  C(function() s:render{width = 4, height = 4, indirect = 5000} end,
    HERE, "indirect", "[0, 1024]")
  C(function() s:render{width = 4, height = 4, roulette = "yes"} end, HERE, "field 'roulette'")
  C(function() s:render{width = 4, height = 4, nee = 1} end, HERE, "field 'nee'")
  C(function() s:render{width = 4, height = 4, ao = 8} end,
    HERE, "field 'ao'", "{samples = N, distance = D} expected, got number")
  C(function() s:render{width = 4, height = 4, ao = {samples = 0, distance = 1}} end,
    HERE, "field 'ao'", "samples", "got 0")
  C(function() s:render{width = 4, height = 4, ao = {samples = 4}} end,
    HERE, "field 'ao'", "distance", "got nil")
  C(function() s:render{width = 4, height = 4, ao = {samples = 4, distance = 0 / 0}} end,
    HERE, "field 'ao'", "distance")
  C(function() s:render{width = 4, height = 4, ao = {samples = 4, distance = -2}} end,
    HERE, "field 'ao'", "got -2")
  C(function() s:render{width = 4, height = 4, ao = {sample = 4, distance = 1}} end,
    HERE, "field 'ao'", "unknown field 'sample'")
  C(function() s:render{width = 4, height = 4, indirct = 2} end,
    HERE, "unknown field 'indirct'", "did you mean 'indirect'?")
  C(function() lancer.load_hdr("/nonexistent/sky.hdr") end, "load_hdr", "cannot open")
  local png = os.tmpname() .. ".png"
  lancer.image{width = 1, height = 1}:save(png)
  C(function() lancer.load_hdr(png) end, "not a Radiance .hdr image")
  os.remove(png)
end)
