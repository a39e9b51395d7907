-- test_sampling.lua: samplers, diffusion cones, area lights, the thin lens
-- and adaptive sampling, against closed forms and docs/numerics.md's targets
-- (T0, T2, T3, T4, T7, H21(d), H23, H24, H28, A2, A3, S5, S6, S8).
local T = require "harness"
local lancer = require "lancer"

-- ---- image helpers -------------------------------------------------------

local function channels(img)
  local v, n = {}, 0
  for y = 1, img.height do
    for x = 1, img.width do
      local r, g, b = img:pixel(x, y)
      v[n + 1], v[n + 2], v[n + 3] = r, g, b
      n = n + 3
    end
  end
  return v
end

-- RMSE over the channels of the pixels mask(x, y) accepts (all by default).
local function rmse(img, ref, mask)
  local a, b = channels(img), ref.values or channels(ref)
  local s, n, w = 0, 0, img.width
  for i = 1, #a, 3 do
    local p = (i - 1) // 3
    if not mask or mask(p % w + 1, p // w + 1) then
      for c = 0, 2 do s = s + (a[i + c] - b[i + c]) ^ 2 end
      n = n + 3
    end
  end
  return math.sqrt(s / n)
end

-- The mean of several renders, as a table rmse() takes for ref.
local function mean_of(imgs)
  local sum = channels(imgs[1])
  for k = 2, #imgs do
    local v = channels(imgs[k])
    for i = 1, #sum do sum[i] = sum[i] + v[i] end
  end
  for i = 1, #sum do sum[i] = sum[i] / #imgs end
  return {values = sum, width = imgs[1].width, height = imgs[1].height}
end

local function mean_rmse(scene, opts, ref, seeds, mask)
  local s = 0
  for seed = 1, seeds do
    local o = {}
    for k, v in pairs(opts) do o[k] = v end
    o.seed = seed
    s = s + rmse(scene:render(o), ref, mask)
  end
  return s / seeds
end

local function same(a, b, what)
  local d = a:diff(b, 0)
  T.eq(d.max, 0, (what or "images") .. ": largest difference")
end

local function no_bad_pixels(img, what)
  T.eq(T.bad_pixels(img), 0, (what or "image") .. ": NaN or infinite channels")
end

-- ---- scenes ----------------------------------------------------------------

-- Scene X of T2: spheres, boxes and a floor under two point lights; only the
-- pixel position is sampled.
local function scene_x()
  local s = lancer.scene{camera = lancer.camera{from = {0, 2, -6}, at = {0, 0.5, 0}, fov = 50}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                     material = lancer.material{color = {0.7, 0.7, 0.6}}})
  s:add(lancer.sphere{center = {-1, 0.8, 0}, radius = 0.8,
                      material = lancer.material{color = {0.9, 0.2, 0.2}}})
  s:add(lancer.sphere{center = {1.2, 0.5, -1}, radius = 0.5,
                      material = lancer.material{color = {0.2, 0.3, 0.9}}})
  s:add(lancer.box{min = {0.2, 0, 0.5}, max = {1.4, 1.2, 1.5},
                   material = lancer.material{color = {0.9, 0.8, 0.2}}})
  s:add(lancer.point_light{position = {3, 5, -4}, intensity = 30})
  s:add(lancer.point_light{position = {-4, 3, -2}, intensity = 10})
  return s
end

-- A floor lit by an emissive sphere, with a box casting a penumbra.
local function penumbra_scene(light_kind)
  local s = lancer.scene{camera = lancer.camera{from = {0, 3, -3}, at = {0, 0, 0.3}, fov = 60}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}, material = lancer.material{}})
  s:add(lancer.box{min = {-0.4, 0, -0.4}, max = {0.4, 0.6, 0.4},
                   material = lancer.material{color = {0.8, 0.5, 0.3}}})
  local lamp = lancer.material{kd = 0, emission = 20}
  if light_kind == "quad" then
    s:add(lancer.quad{corner = {-0.5, 2, 0.5}, u = {1, 0, 0}, v = {0, 0, 1}, material = lamp})
  else
    s:add(lancer.sphere{center = {0, 2, 1}, radius = 0.5, material = lamp})
  end
  return s
end

-- ---- T0: determinism and independence ------------------------------------

T.test("T0 every sampler: bit-identical on 1 and 3 threads and from run to run", function()
  local s = penumbra_scene()
  s:add(lancer.sphere{center = {1.2, 0.5, 0}, radius = 0.5,
                      material = lancer.material{kd = 0.2, kr = 0.8, glossiness = 10,
                                                 cone_samples = 4}})
  s.camera = lancer.camera{from = {0, 3, -3}, at = {0, 0, 0.3}, fov = 60, aperture = 0.2}
  for _, sampler in ipairs{"sobol", "jitter", "random"} do
    local o = {width = 24, height = 18, samples = 4, light_samples = 4, sampler = sampler,
               seed = 3, frame = 2}
    o.threads = 1
    local a = s:render(o)
    o.threads = 3
    local b = s:render(o)
    local c = s:render(o)
    same(a, b, sampler .. " 1 vs 3 threads")
    same(b, c, sampler .. " run to run")
    no_bad_pixels(a, sampler)
  end
end)

T.test("T0 another seed or frame gives an independent image; a frame alone is the same", function()
  -- Independent images average down: the mean of K renders has 1/K of one
  -- render's MSE (measured 5.3..13.6 for K = 8, seeds and frames alike, as
  -- for the plainly independent 'random' sampler). Copies would give 1,
  -- noise correlated at 0.5 about 1.8.
  local s = penumbra_scene()
  local W, H, K = 48, 36, 8
  local ref = mean_of{(s:render{width = W, height = H, light_samples = 4096})}
  for _, what in ipairs{"seed", "frame"} do
    local single, imgs = 0, {}
    for k = 1, K do
      local o = {width = W, height = H, light_samples = 2, seed = 1}
      o[what] = k + 1
      imgs[k] = s:render(o)
      single = single + rmse(imgs[k], ref) ^ 2 / K
    end
    local m = mean_of(imgs)
    local sum = 0
    for i, v in ipairs(m.values) do sum = sum + (v - ref.values[i]) ^ 2 end
    local ratio = single / (sum / #m.values)
    assert(ratio >= K / 2 and ratio <= 2 * K, ("%ss: MSE of one / MSE of the mean of %d = %.2f")
      :format(what, K, ratio))
  end
  -- frame 5 alone, and after frames 0..4 in the same scene
  local o = {width = W, height = H, light_samples = 2, frame = 5}
  local alone = s:render(o)
  for f = 0, 4 do o.frame = f; s:render(o) end
  o.frame = 5
  same(alone, s:render(o), "frame 5 alone and in sequence")
end)

-- ---- T2: stratified pixel sampling pays ----------------------------------

T.test("T2 Sobol' and jitter at 8 spp beat random at 16 spp; Sobol' slope <= -0.65", function()
  local s = scene_x()
  local W, H = 32, 24
  local ref = mean_of{(s:render{width = W, height = H, samples = 4096})}
  local random16 = mean_rmse(s, {width = W, height = H, samples = 16, sampler = "random"}, ref, 4)
  local sobol8 = mean_rmse(s, {width = W, height = H, samples = 8}, ref, 4)
  local jitter8 = mean_rmse(s, {width = W, height = H, samples = 8, sampler = "jitter"}, ref, 4)
  assert(sobol8 <= random16, ("Sobol' 8 spp RMSE %.5f > random 16 spp %.5f"):format(sobol8, random16))
  assert(jitter8 <= random16, ("jitter 8 spp RMSE %.5f > random 16 spp %.5f"):format(jitter8, random16))
  -- least-squares slope of log RMSE against log spp over 16..256
  local xs, ys = {}, {}
  for _, n in ipairs{16, 64, 256} do
    xs[#xs + 1] = math.log(n)
    ys[#ys + 1] = math.log(mean_rmse(s, {width = W, height = H, samples = n}, ref, 2))
  end
  local mx, my = (xs[1] + xs[2] + xs[3]) / 3, (ys[1] + ys[2] + ys[3]) / 3
  local sxy, sxx = 0, 0
  for i = 1, 3 do sxy, sxx = sxy + (xs[i] - mx) * (ys[i] - my), sxx + (xs[i] - mx) ^ 2 end
  assert(sxy / sxx <= -0.65, ("Sobol' RMSE slope %.3f"):format(sxy / sxx))
end)

-- ---- area lights: A2, A3, T3, S6 ---------------------------------------------

-- The pixel under the camera (looking straight down at `at`) of a diffuse
-- plane kd = 0.8, reads kd * E / pi.
local function probe(lamp, at, opts)
  local sc = lancer.scene{camera = lancer.camera{from = {at[1], at[2] + 0.5, at[3]}, at = at,
                                                 up = {0, 0, 1}, fov = 0.5}}
  sc:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                      material = lancer.material{kd = 0.8}})
  lamp(sc)
  local o = {width = 1, height = 1}
  for k, v in pairs(opts or {}) do o[k] = v end
  local img, st = sc:render(o)
  no_bad_pixels(img, "probe")
  return img:pixel(1, 1) * math.pi / 0.8, st
end

-- E/L of a convex polygon seen from the origin with normal +y (Lambert's
-- formula: half the sum over edges of the angle times n.g).
local function polygon_e(verts)
  local e = 0
  for i = 1, #verts do
    local a, b = verts[i], verts[i % #verts + 1]
    local la = math.sqrt(a[1] ^ 2 + a[2] ^ 2 + a[3] ^ 2)
    local lb = math.sqrt(b[1] ^ 2 + b[2] ^ 2 + b[3] ^ 2)
    local cos = (a[1] * b[1] + a[2] * b[2] + a[3] * b[3]) / (la * lb)
    local c = {a[2] * b[3] - a[3] * b[2], a[3] * b[1] - a[1] * b[3], a[1] * b[2] - a[2] * b[1]}
    local lc = math.sqrt(c[1] ^ 2 + c[2] ^ 2 + c[3] ^ 2)
    e = e + math.acos(math.max(-1, math.min(1, cos))) * c[2] / lc
  end
  return math.abs(e) / 2
end

T.test("A2 sampled sphere light: E/L = 0.0490874 and 0.0351241 within 0.5 %, 0.2 % converged", function()
  local function lamp(sc)
    sc:add(lancer.sphere{center = {0, 2, 0}, radius = 0.25,
                         material = lancer.material{kd = 0, emission = 1}})
  end
  for _, case in ipairs{{{0, 0, 0}, 0.0490874}, {{1, 0, 0}, 0.0351241}} do
    local e16, st = probe(lamp, case[1], {light_samples = 16})
    T.eq(st.rays.light, 16, "16 light rays")
    T.eq(st.rays.shadow, 0, "no centre ray")
    assert(math.abs(e16 / case[2] - 1) <= 0.005, ("16 samples: E/L %.7g"):format(e16))
    local e = probe(lamp, case[1], {light_samples = 4096})
    assert(math.abs(e / case[2] - 1) <= 0.002, ("4096 samples: E/L %.7g"):format(e))
  end
end)

T.test("A3 sampled rectangle light: E/L = 0.7522747 under the unit square; Lambert's formula off-centre", function()
  local L = 3
  local function lamp(sc)
    sc:add(lancer.quad{corner = {-0.5, 1, -0.5}, u = {1, 0, 0}, v = {0, 0, 1},
                       material = lancer.material{kd = 0, emission = L}})
  end
  local e = probe(lamp, {0, 0, 0}, {light_samples = 64}) / L
  assert(math.abs(e / 0.7522747 - 1) <= 0.005, ("64 samples: E/L %.7g"):format(e))
  e = probe(lamp, {0, 0, 0}, {light_samples = 4096}) / L
  assert(math.abs(e / 0.7522747 - 1) <= 0.002, ("4096 samples: E/L %.7g"):format(e))
  -- off-centre, and the quad tilted: Lambert's polygon formula
  local at = {0.7, 0, 0.2}
  local v = {{-0.5, 1, -0.5}, {0.5, 1, -0.5}, {0.5, 1, 0.5}, {-0.5, 1, 0.5}}
  for i, p in ipairs(v) do v[i] = {p[1] - at[1], p[2] - at[2], p[3] - at[3]} end
  e = probe(lamp, at, {light_samples = 1024}) / L
  local want = polygon_e(v)
  assert(math.abs(e / want - 1) <= 0.005, ("off-centre E/L %.7g, Lambert %.7g"):format(e, want))
  local function tilted(sc)
    sc:add(lancer.quad{corner = {-0.5, 0.8, -0.5}, u = {1, 0.4, 0}, v = {0, 0, 1},
                       material = lancer.material{kd = 0, emission = L}})
  end
  e = probe(tilted, {0, 0, 0}, {light_samples = 1024}) / L
  want = polygon_e{{-0.5, 0.8, -0.5}, {0.5, 1.2, -0.5}, {0.5, 1.2, 0.5}, {-0.5, 0.8, 0.5}}
  assert(math.abs(e / want - 1) <= 0.005, ("tilted E/L %.7g, Lambert %.7g"):format(e, want))
end)

T.test("A3 a box light under its bottom face equals that face as a quad light", function()
  local function box(sc)
    sc:add(lancer.box{min = {-0.5, 1, -0.5}, max = {0.5, 1.5, 0.5},
                      material = lancer.material{kd = 0, emission = 1}})
  end
  local e, st = probe(box, {0, 0, 0}, {light_samples = 1024})
  assert(math.abs(e / 0.7522747 - 1) <= 0.005, ("box E/L %.7g"):format(e))
  T.eq(st.rays.light, 1024, "one ray per sample")
  -- beside the box, two faces face the point: the sum of both quads
  local at = {1.5, 0, 0}
  e = probe(box, at, {light_samples = 4096})
  local bottom = {{-2, 1, -0.5}, {-1, 1, -0.5}, {-1, 1, 0.5}, {-2, 1, 0.5}}
  local side = {{-1, 1, -0.5}, {-1, 1.5, -0.5}, {-1, 1.5, 0.5}, {-1, 1, 0.5}}
  local want = polygon_e(bottom) + polygon_e(side)
  assert(math.abs(e / want - 1) <= 0.005, ("two faces: E/L %.7g, Lambert %.7g"):format(e, want))
end)

T.test("T3 penumbra: stratified light samples at 8 beat random at 16; S6 ray kinds", function()
  local s = penumbra_scene()
  local W, H = 32, 24
  local ref = s:render{width = W, height = H, light_samples = 4096}
  -- penumbra pixels: between 5 % and 95 % of the unshadowed value
  local refv = channels(ref)
  local open = (function()
    local o = lancer.scene{camera = lancer.camera{from = {0, 3, -3}, at = {0, 0, 0.3}, fov = 60}}
    o:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}, material = lancer.material{}})
    o:add(lancer.sphere{center = {0, 2, 1}, radius = 0.5,
                        material = lancer.material{kd = 0, emission = 20}})
    return channels(o:render{width = W, height = H, light_samples = 4096})
  end)()
  local n = 0
  local function penumbra(x, y)
    local i = ((y - 1) * W + x - 1) * 3 + 1
    local f = refv[i] / open[i]
    return f > 0.05 and f < 0.95
  end
  for y = 1, H do for x = 1, W do if penumbra(x, y) then n = n + 1 end end end
  assert(n >= 20, "penumbra pixels: " .. n)
  local r16 = mean_rmse(s, {width = W, height = H, light_samples = 16, sampler = "random"},
                        ref, 4, penumbra)
  local s8 = mean_rmse(s, {width = W, height = H, light_samples = 8}, ref, 4, penumbra)
  assert(s8 <= r16, ("Sobol' 8: %.5f, random 16: %.5f"):format(s8, r16))
  -- S6: area lights spawn light rays, never point-light shadow rays
  local _, st = s:render{width = W, height = H, light_samples = 8}
  T.eq(st.rays.shadow, 0, "shadow rays with only an area light")
  assert(st.rays.light > 0 and st.effects.area and not st.effects.emitter, "area effect")
  _, st = s:render{width = W, height = H, light_samples = 0}
  T.eq(st.rays.light, 0, "light rays with light_samples = 0")
  assert(st.rays.shadow > 0 and st.effects.emitter and not st.effects.area, "emitter effect")
  _, st = scene_x():render{width = W, height = H}
  T.eq(st.rays.light, 0, "light rays with only point lights")
  _, st = s:render{width = W, height = H, light_samples = 8, shadows = false}
  T.eq(st.rays.light, 0, "light rays with shadows off")
  no_bad_pixels(ref)
end)

-- ---- glossy cones: H21(d), H23, H24, H28, T4, S5, S8 -----------------------

T.test("H28 glossiness 0, 1e-20 degrees and glossy = false are bit-identical mirrors", function()
  local function scene(gl)
    local s = scene_x()
    s:add(lancer.sphere{center = {0, 1.5, 1}, radius = 0.6,
                        material = lancer.material{kd = 0.1, kr = 0.9, glossiness = gl}})
    return s
  end
  local o = {width = 24, height = 18}
  local mirror, st = scene(0):render(o)
  T.eq(st.rays.glossy, 0, "no glossy ray")
  assert(st.rays.reflection > 0, "reflections")
  same(mirror, scene(1e-20):render(o), "glossiness 1e-20")
  o.glossy = false
  local off, st2 = scene(5):render(o)
  same(mirror, off, "glossy = false")
  T.eq(st2.rays.glossy, 0, "glossy = false: no glossy ray")
  T.eq(st2.rays.reflection, st.rays.reflection, "glossy = false: the mirror's rays")
end)

T.test("H21(d) glossy furnace: a kr = 1 cone of 10 degrees shows the background exactly", function()
  local B = 0.5
  for _, gl in ipairs{10, 45, 80} do
    local s = lancer.scene{camera = lancer.camera{from = {0, 0, -4}, at = {0, 0, 0}, fov = 40},
                           background = B}
    s:add(lancer.sphere{center = {0, 0, 0}, radius = 1,
                        material = lancer.material{kd = 0, kr = 1, glossiness = gl,
                                                   cone_samples = 16}})
    local img, st = s:render{width = 24, height = 24}
    assert(st.rays.glossy > 0, "glossy rays")
    for y = 1, 24 do
      for x = 1, 24 do
        local r = img:pixel(x, y)
        T.near(r, B, 1 / 255, ("cone %g: pixel (%d, %d)"):format(gl, x, y))
      end
    end
    T.eq(st.self_hits, 0, "self-hits")
  end
end)

-- H23's scene: a glossy floor seen at a slant, reflecting an emissive
-- vertical bar (by default 32 x 24 pixels and a bar one pixel wide where it
-- stands); returns the column profile summed over the rows from the bar's
-- foot down (its reflection), the image and the stats.
local function line_profile(opts, half_width, W)
  half_width, W = half_width or 0.07, W or 32
  local H = W * 3 // 4
  local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 0.2, 0}, fov = 40}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                     material = lancer.material{kd = 0, kr = 1, glossiness = 5,
                                                cone_samples = 16}})
  s:add(lancer.box{min = {-half_width, 0, 2}, max = {half_width, 3, 2.02},
                   material = lancer.material{kd = 0, emission = 1}})
  local o = {width = W, height = H, light_samples = 0}
  for k, v in pairs(opts or {}) do o[k] = v end
  local img, st = s:render(o)
  local prof = {}
  for x = 1, W do
    local sum = 0
    for y = H * 13 // 24, H do sum = sum + img:pixel(x, y) end
    prof[x] = sum
  end
  return prof, img, st
end

-- Local maxima whose prominence is over frac of the highest value.
local function peaks(p, frac)
  local top = 0
  for _, v in ipairs(p) do top = math.max(top, v) end
  local count = 0
  for i = 2, #p - 1 do
    if p[i] > p[i - 1] and p[i] >= p[i + 1] then
      local left, right = p[i], p[i]
      for j = i - 1, 1, -1 do
        if p[j] > p[i] then break end
        left = math.min(left, p[j])
      end
      for j = i + 1, #p do
        if p[j] > p[i] then break end
        right = math.min(right, p[j])
      end
      if p[i] - math.max(left, right) > frac * top then count = count + 1 end
    end
  end
  return count
end

T.test("H23 a thin line in a glossy floor: one peak, no duplicated reflections", function()
  local prof, _, st = line_profile()
  assert(st.rays.glossy > 0 and st.rays.glossy % 16 == 0, "16 cone rays per floor hit")
  T.eq(peaks(prof, 0.05), 1, "peaks with prominence > 5 %")
  for seed = 2, 8 do
    T.eq(peaks(line_profile{seed = seed}, 0.05), 1, "seed " .. seed .. ": peaks")
  end
  -- the mean of 8 seeds matches the converged profile (1024 cone rays) within 2 %
  local ref = line_profile({cone_samples = 1024})
  local mean = {}
  for seed = 1, 8 do
    local p = line_profile({seed = seed})
    for x, v in ipairs(p) do mean[x] = (mean[x] or 0) + v / 8 end
  end
  local top = 0
  for _, v in ipairs(ref) do top = math.max(top, v) end
  for x, v in ipairs(mean) do
    T.near(v, ref[x], 0.02 * top, "mean profile at column " .. x)
  end
  T.eq(peaks(ref, 0.05), 1, "converged profile peaks")
end)

T.test("T4 stratified cone rays: RMSE at 16 at least 1.5x lower than independent", function()
  -- The bar's reflected edges, 4 pixels apart: a bar thinner than one
  -- stratum of the cone gains little from stratifying (a 0.3-pixel line:
  -- RMSE ratio 1.04 measured), edges gain the most (docs/numerics.md 3.2).
  local _, ref = line_profile({cone_samples = 1024}, 0.15, 64)
  local function err(sampler)
    local s = 0
    for seed = 1, 4 do
      local _, img = line_profile({seed = seed, sampler = sampler}, 0.15, 64)
      s = s + rmse(img, ref, function(_, y) return y >= 30 end)
    end
    return s / 4
  end
  local strat, indep = err("sobol"), err("random")
  assert(indep / strat >= 1.5, ("RMSE Sobol' %.5f, random %.5f: ratio %.2f"):format(
    strat, indep, indep / strat))
end)

T.test("H24 glossy cone at grazing and along the axes: no NaN, nothing traced into the surface", function()
  -- a floor seen at 85 degrees from its normal, cone 20 degrees
  local s = lancer.scene{camera = lancer.camera{from = {0, 0.35, -4}, at = {0, 0, 0}, fov = 30},
                         background = 0.5}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                     material = lancer.material{kd = 0, kr = 1, glossiness = 20,
                                                cone_samples = 8}})
  local img, st = s:render{width = 32, height = 24}
  no_bad_pixels(img)
  T.eq(st.self_hits, 0, "self-hits")
  -- every floor pixel sees the uniform background: exactly B (folded samples
  -- keep the energy)
  for y = 13, 24 do
    for x = 1, 32 do T.near(img:pixel(x, y), 0.5, 1 / 255, ("pixel (%d, %d)"):format(x, y)) end
  end
  -- mirror directions exactly along +-x, +-y, +-z
  for _, n in ipairs{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}} do
    local sc = lancer.scene{camera = lancer.camera{from = {2 * n[1], 2 * n[2], 2 * n[3]},
                                                   at = {0, 0, 0}, fov = 1,
                                                   up = n[2] == 0 and {0, 1, 0} or {1, 0, 0}},
                            background = 0.25}
    sc:add(lancer.plane{point = {0, 0, 0}, normal = n,
                        material = lancer.material{kd = 0, kr = 1, glossiness = 20}})
    local im, st2 = sc:render{width = 3, height = 3}
    no_bad_pixels(im)
    T.near(im:pixel(2, 2), 0.25, 1e-12, "axis " .. table.concat(n, ","))
    T.eq(st2.rays.glossy, 9 * 16, "cone rays")
  end
end)

T.test("S5 a glossy floor: glossy rays = W*H*spp*M exactly; kr under the cutoff: none", function()
  local function floor(kr, M)
    local s = lancer.scene{camera = lancer.camera{from = {0, 2, 0}, at = {0, 0, 0},
                                                  up = {0, 0, 1}, fov = 60},
                           max_depth = 1, background = 0.3}
    s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                       material = lancer.material{kr = kr, glossiness = 8,
                                                  cone_samples = M}})
    s:add(lancer.point_light{position = {0, 3, 0}, intensity = 4})
    return s
  end
  local W, H = 12, 10
  for _, M in ipairs{1, 5, 16} do
    local _, st = floor(0.5, M):render{width = W, height = H, samples = 2}
    T.eq(st.rays.glossy, W * H * 2 * M, ("M = %d: glossy rays"):format(M))
    T.eq(st.rays.reflection, 0, "no mirror rays")
  end
  local _, st = floor(0.5, 16):render{width = W, height = H, cone_samples = 3}
  T.eq(st.rays.glossy, W * H * 3, "cone_samples overrides the material")
  local img, st2 = floor(1e-4, 16):render{width = W, height = H}
  T.eq(st2.rays.glossy, 0, "kr 1e-4 < cutoff: glossy rays")
  T.eq(st2.rays.cut, W * H, "kr 1e-4: cut")
  local plain = floor(0, 16):render{width = W, height = H}
  local d = img:diff(plain, 1 / 255)
  T.eq(d.within, 1, "image unchanged within 1/255")
end)

T.test("S8 a glossy material and an emitter nothing lit uses cost no ray", function()
  local s = scene_x()
  local _, before = s:render{width = 16, height = 12}
  lancer.material{kr = 1, glossiness = 10}             -- defined, never used
  local _, after = s:render{width = 16, height = 12}
  T.eq(after.rays.glossy, 0, "glossy rays")
  T.eq(after.effects.glossy, false, "glossy effect")
  local q = lancer.scene{camera = lancer.camera{from = {0, 0, -3}, at = {0, 0, 0}}}
  q:add(lancer.sphere{center = {0, 0, 0}, radius = 1, material = lancer.material{kd = 0, kr = 0.5}})
  q:add(lancer.sphere{center = {2, 2, 2}, radius = 0.5, material = lancer.material{kd = 0, emission = 3}})
  local _, st = q:render{width = 8, height = 8}
  T.eq(st.rays.light, 0, "an emitter that lights no kd/ks material: light rays")
  T.eq(st.effects.area, false, "area effect")
  T.eq(before.rays.light, 0, "point lights only")
end)

T.test("explain: glossy and light rays add up to the pixel; generic path bit-identical", function()
  local s = penumbra_scene("quad")
  s:add(lancer.sphere{center = {1.2, 0.5, 0}, radius = 0.5,
                      material = lancer.material{kd = 0.3, kr = 0.7, glossiness = 6,
                                                 cone_samples = 4, ks = 0.5}})
  local W, H = 24, 18
  local o = {width = W, height = H, samples = 2, light_samples = 3}
  local img = s:render(o)
  local kinds = {}
  local glossy_pixel       -- one that sees the glossy sphere
  for x = 1, W do
    for y = 1, H do
      local t = s:explain{x = x, y = y, width = W, height = H, light_samples = 3}
      if not glossy_pixel and t.hit and t.hit.material == 4 then glossy_pixel = {x, y} end
    end
  end
  assert(glossy_pixel, "some pixel sees the glossy sphere")
  for _, xy in ipairs{glossy_pixel, {12, 14}, {5, 5}} do
    local r0, g0, b0 = img:pixel(xy[1], xy[2])
    local r, g, b = 0, 0, 0
    for sample = 1, 2 do
      local tree = s:explain{x = xy[1], y = xy[2], width = W, height = H, samples = 2,
                             light_samples = 3, sample = sample}
      r, g, b = r + tree.contribution[1] / 2, g + tree.contribution[2] / 2,
                b + tree.contribution[3] / 2
      local function walk(node)
        for _, c in ipairs(node.rays) do kinds[c.kind] = true; walk(c) end
      end
      walk(tree)
    end
    T.near(r, r0, 1e-5, "red"); T.near(g, g0, 1e-5, "green"); T.near(b, b0, 1e-5, "blue")
  end
  assert(kinds.glossy and kinds.light, "glossy and light rays in the trees")
  o.generic = true
  same(img, s:render(o), "generic path")
end)

-- ---- depth of field --------------------------------------------------------

T.test("lens: the plane in focus is as sharp as through a pinhole; blur = A|z-F|/z", function()
  local function scene(aperture)
    local s = lancer.scene{camera = lancer.camera{from = {0, 0, -5}, at = {0, 0, 0}, fov = 40,
                                                  aperture = aperture}}
    s:add(lancer.quad{corner = {-1, -1, 0}, u = {1.3, 0, 0}, v = {0, 2, 0},
                      material = lancer.material{color = {0.8, 0.6, 0.4}}})
    s:add(lancer.point_light{position = {0, 0, -5}, intensity = 25})
    return s
  end
  local o = {width = 40, height = 30, samples = 16}
  local pin, lens = scene(0):render(o), scene(0.5):render(o)
  local d = lens:diff(pin, 1e-6)
  assert(d.max < 1e-6, ("in focus: largest difference %g"):format(d.max))
  local _, st = scene(0.5):render(o)
  assert(st.effects.lens, "lens effect")
  -- a sphere of radius R at z = 10 (15 from the lens, focus at 5): each of
  -- its points blurs into a disc of diameter A|z - F|/z on the plane in
  -- focus, so the lit part of the middle row spans 2RF/z + A|z - F|/z
  local F, z, W, R = 5, 15, 64, 0.3
  local plane = 2 * F * math.tan(math.rad(20))            -- focus plane width
  for _, A in ipairs{0.5, 1} do
    local s = lancer.scene{camera = lancer.camera{from = {0, 0, -5}, at = {0, 0, 0}, fov = 40,
                                                  aperture = A, focus = F}}
    s:add(lancer.sphere{center = {0, 0, 10}, radius = R,
                        material = lancer.material{kd = 0, emission = 1}})
    local img = s:render{width = W, height = W, samples = 256}
    local row, top = {}, 0
    for x = 1, W do row[x] = img:pixel(x, W // 2 + 1); top = math.max(top, row[x]) end
    local lit = 0
    for x = 1, W do if row[x] > 0.02 * top then lit = lit + 1 end end
    local want = (2 * R * F / z + A * (z - F) / z) * W / plane
    T.near(lit, want, 1.5, ("aperture %g: lit pixels across"):format(A))
  end
end)

T.test("H1/H2 with a lens, glossy cones and area lights: scaled and moved, the same picture", function()
  -- The sampled effects keep scale and translation invariance: their
  -- random numbers do not depend on where the scene is, and the lens's
  -- aperture and focus scale with it (a test that caught them left out).
  local s = penumbra_scene("quad")
  s:add(lancer.sphere{center = {1.2, 0.5, 0}, radius = 0.5,
                      material = lancer.material{kd = 0.3, kr = 0.7, glossiness = 6,
                                                 cone_samples = 4}})
  s.camera = lancer.camera{from = {0, 3, -3}, at = {0, 0, 0.3}, fov = 60, aperture = 0.3,
                           focus = 3.2}
  local o = {width = 32, height = 24, samples = 4, light_samples = 4}
  local ref = s:render(o)
  for _, v in ipairs{{1e-3}, {1e3}, {1, {1e6, 5e5, 3e5}}} do
    local img = s:transformed(v[1], v[2]):render(o)
    local d = img:diff(ref, 1 / 255)
    assert(d.within >= 0.999, ("scale %g, offset %s: %.3f %% within 1/255 (worst %g)")
      :format(v[1], v[2] and "1e6" or "0", 100 * d.within, d.max))
    no_bad_pixels(img)
  end
end)

-- ---- adaptive sampling: T7 ---------------------------------------------------

T.test("T7 adaptive: the RMSE of 256 spp with at most half the camera rays, no bias", function()
  -- 80 % flat background; a glossy sphere on a sphere light's soft shadow
  local function scene()
    local s = lancer.scene{camera = lancer.camera{from = {0, 1, -6}, at = {0, 0.4, 0}, fov = 30},
                           background = {0.2, 0.3, 0.5}}
    s:add(lancer.quad{corner = {-0.6, 0, -0.6}, u = {1.2, 0, 0}, v = {0, 0, 1.2},
                      material = lancer.material{}})
    s:add(lancer.sphere{center = {0, 0.35, 0}, radius = 0.35,
                        material = lancer.material{kd = 0.3, kr = 0.6, glossiness = 15,
                                                   cone_samples = 1}})
    s:add(lancer.sphere{center = {0.8, 1.6, -0.5}, radius = 0.3,
                        material = lancer.material{kd = 0, emission = 8}})
    return s
  end
  local s = scene()
  local W, H = 32, 24
  local o = {width = W, height = H, light_samples = 1}
  local function with(t) local r = {} for k, v in pairs(o) do r[k] = v end
    for k, v in pairs(t) do r[k] = v end return r end
  local ref = s:render(with{samples = 4096, seed = 99})
  local uni, ust = s:render(with{samples = 256})
  local target = rmse(uni, ref)
  local ada, ast = s:render(with{samples = 1024, noise = 0.1, min_samples = 16})
  local got = rmse(ada, ref)
  assert(got <= target, ("adaptive RMSE %.5f > uniform 256's %.5f"):format(got, target))
  T.eq(ast.rays.camera, ast.samples, "camera rays = samples used")
  assert(ast.samples <= 0.5 * ust.samples, ("adaptive used %d samples, uniform 256: %d")
    :format(ast.samples, ust.samples))
  -- no bias: mean difference under 0.5/255
  local a, r = channels(ada), channels(ref)
  local bias = 0
  for i = 1, #a do bias = bias + (a[i] - r[i]) end
  bias = bias / #a
  assert(math.abs(bias) <= 0.5 / 255, ("bias %.3g"):format(bias))
  assert(ast.converged >= 0.95 * W * H, ("converged %d of %d"):format(ast.converged, W * H))
  T.eq(ust.converged, 0, "no adaptive: no pixel stops early")
  T.check_error(function() s:render(with{noise = 0.01, sampler = "jitter"}) end,
                "field 'sampler'", "adaptive")
end)

-- ---- bad input ----------------------------------------------------------------

T.test("bad sampling fields and options name themselves", function()
  local s = scene_x()
  local cases = {
    {{sampler = "halton"}, "field 'sampler'"},
    {{light_samples = -1}, "field 'light_samples'"},
    {{light_samples = 5000}, "field 'light_samples'"},
    {{cone_samples = -2}, "field 'cone_samples'"},
    {{noise = 0 / 0}, "field 'noise'"},
    {{noise = -1}, "field 'noise'"},
    {{noise = math.huge}, "field 'noise'"},
    {{min_samples = 0}, "field 'min_samples'"},
    {{max_depth = -2}, "field 'max_depth'"},
    {{frame = -1}, "field 'frame'"},
    {{frame = 1.5}, "field 'frame'"},
    {{glossy = 1}, "field 'glossy'"},
  }
  for _, c in ipairs(cases) do
    local o = {width = 2, height = 2}
    for k, v in pairs(c[1]) do o[k] = v end
    T.check_error(function() s:render(o) end, c[2])
  end
  T.check_error(function() lancer.material{glossiness = 90} end, "field 'glossiness'", "[0, 90)")
  T.check_error(function() lancer.material{glossiness = 0 / 0} end, "field 'glossiness'")
  T.check_error(function() lancer.material{cone_samples = 0} end, "field 'cone_samples'")
  T.check_error(function() lancer.camera{from = {0, 0, 0}, at = {0, 0, 1}, aperture = -1} end,
                "field 'aperture'")
  T.check_error(function() lancer.camera{from = {0, 0, 0}, at = {0, 0, 1}, focus = 0 / 0} end,
                "field 'focus'")
  local m = lancer.material{glossiness = 7.5, cone_samples = 9}
  T.eq(m.glossiness, 7.5, "material.glossiness")
  T.eq(m.cone_samples, 9, "material.cone_samples")
  local c = lancer.camera{from = {0, 0, 0}, at = {0, 0, 1}, aperture = 0.1, focus = 3}
  T.eq(c.aperture, 0.1, "camera.aperture")
  T.eq(c.focus, 3, "camera.focus")
end)
