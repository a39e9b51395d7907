-- test_shading.lua: rendered pixels against closed forms, and exact ray counts.
local T = require "harness"
local lancer = require "lancer"

local TOL = 1 / 255           -- the issue's bar; float rounding is ~1e-6

-- The camera model of the README, in Lua: the ray through pixel (i, j),
-- 0-based, at its centre.
local function norm(v)
  local l = math.sqrt(v[1] ^ 2 + v[2] ^ 2 + v[3] ^ 2)
  return {v[1] / l, v[2] / l, v[3] / l}
end
local function cross(a, b)
  return {a[2] * b[3] - a[3] * b[2], a[3] * b[1] - a[1] * b[3], a[1] * b[2] - a[2] * b[1]}
end
local function dot(a, b) return a[1] * b[1] + a[2] * b[2] + a[3] * b[3] end
local function sub(a, b) return {a[1] - b[1], a[2] - b[2], a[3] - b[3]} end

local function pixel_ray(cam, w, h, i, j)
  local f = norm(sub(cam.at, cam.from))
  local r = norm(cross(f, cam.up or {0, 1, 0}))
  local u = cross(r, f)
  local tx = math.tan(math.rad(cam.fov) / 2)
  local ty = tx * h / w
  local sx = (2 * (i + 0.5) / w - 1) * tx
  local sy = (1 - 2 * (j + 0.5) / h) * ty
  return cam.from, norm{f[1] + sx * r[1] + sy * u[1], f[2] + sx * r[2] + sy * u[2],
                        f[3] + sx * r[3] + sy * u[3]}
end

-- Largest |pixel - expected(i, j)| over the image, and where.
local function worst(img, expected)
  local worst_d, wx, wy = 0, 0, 0
  for y = 1, img.height do
    for x = 1, img.width do
      local r, g, b = img:pixel(x, y)
      local er, eg, eb = expected(x - 1, y - 1)
      for _, d in ipairs{math.abs(r - er), math.abs(g - eg), math.abs(b - eb)} do
        if not (d <= worst_d) then worst_d, wx, wy = d, x, y end
      end
    end
  end
  return worst_d, wx, wy
end

local function assert_close(img, expected, tol, what)
  local d, x, y = worst(img, expected)
  assert(d <= tol, ("%s: worst pixel (%d, %d) off by %.3g > %.3g"):format(what, x, y, d, tol))
  T.eq(T.bad_pixels(img), 0, "NaN or infinite channels")
end

T.test("diffuse plane under one point light matches kd*I*h/d^3 per pixel", function()
  local h, I, kd = 3, 20, 0.5
  local cam = {from = {0, 8, 0}, at = {0, 0, 0}, up = {0, 0, 1}, fov = 70}
  local scene = lancer.scene{camera = lancer.camera(cam)}
  scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                         material = lancer.material{kd = kd}})
  scene:add(lancer.point_light{position = {0.5, h, -0.25}, intensity = I})
  local W, H = 64, 48
  local img, stats = scene:render{width = W, height = H}
  local L = {0.5, h, -0.25}
  assert_close(img, function(i, j)
    local o, d = pixel_ray(cam, W, H, i, j)
    local t = -o[2] / d[2]
    local p = {o[1] + t * d[1], 0, o[3] + t * d[3]}
    local tol = sub(L, p)
    local dist = math.sqrt(dot(tol, tol))
    local v = kd * I * (h / dist) / dist ^ 2
    return v, v, v
  end, 1e-5, "plane")
  T.eq(stats.rays.camera, W * H, "camera rays")
  T.eq(stats.rays.shadow, W * H, "one shadow ray per pixel: the plane faces the light")
  T.eq(stats.rays.reflection, 0, "no mirror in the scene")
end)

T.test("a plane of albedo 0.5 lit head-on from height h by intensity h^2 reads 0.5", function()
  local scene = lancer.scene{camera = lancer.camera{from = {0, 2, 0}, at = {0, 0, 0},
                                                    up = {0, 0, 1}, fov = 1}}
  scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                         material = lancer.material{color = 0.5}})
  scene:add(lancer.point_light{position = {0, 7, 0}, intensity = 49})
  local img = scene:render{width = 1, height = 1}
  local r = img:pixel(1, 1)
  T.near(r, 0.5, 1e-6, "centre pixel")
end)

local function inside_sphere(cam_from)
  local R, I, kd = 2, 12, 0.8
  local scene = lancer.scene{camera = lancer.camera{from = cam_from, at = {0.3, 0.1, 1},
                                                    fov = 100}}
  scene:add(lancer.sphere{center = {0, 0, 0}, radius = R,
                          material = lancer.material{kd = kd, color = {1, 0.5, 0.25}}})
  scene:add(lancer.point_light{position = {0, 0, 0}, intensity = I})
  local img = scene:render{width = 40, height = 30}
  local v = kd * I / R ^ 2
  assert_close(img, function() return v, v * 0.5, v * 0.25 end, 1e-5, "inside sphere")
end

T.test("camera and light at the centre of a sphere: uniform kd*I/R^2", function()
  inside_sphere{0, 0, 0}
end)

T.test("camera off-centre (0.7R) inside the sphere: still uniform", function()
  inside_sphere{0.7 * 2 / math.sqrt(3), 0.7 * 2 / math.sqrt(3), -0.7 * 2 / math.sqrt(3)}
end)

T.test("a white sphere under a red and a green light shows their sum", function()
  local cam = {from = {0, 0, -5}, at = {0, 0, 0}, fov = 40}
  local scene = lancer.scene{camera = lancer.camera(cam)}
  scene:add(lancer.sphere{center = {0, 0, 0}, radius = 1})
  local red, green = {-3, 0, -4}, {3, 0, -4}
  scene:add(lancer.point_light{position = red, color = {1, 0, 0}, intensity = 30})
  scene:add(lancer.point_light{position = green, color = {0, 1, 0}, intensity = 30})
  local W, H = 41, 41
  local img = scene:render{width = W, height = H}
  local function lit(L, p, n)
    local tl = sub(L, p)
    local d = math.sqrt(dot(tl, tl))
    local c = dot(n, tl) / d
    return c > 0 and 30 * c / d ^ 2 or 0
  end
  assert_close(img, function(i, j)
    local o, d = pixel_ray(cam, W, H, i, j)
    local b = dot(o, d)
    local disc = b * b - (dot(o, o) - 1)
    if disc < 0 then return 0, 0, 0 end
    local t = -b - math.sqrt(disc)
    local p = {o[1] + t * d[1], o[2] + t * d[2], o[3] + t * d[3]}
    local n = norm(p)
    return lit(red, p, n), lit(green, p, n), 0
  end, 1e-5, "two lights")
  -- The centre is lit by both: the channels add.
  local r, g, b = img:pixel(21, 21)
  assert(r > 0.3 and g > 0.3 and b == 0, ("centre %g %g %g"):format(r, g, b))
  T.near(r, g, 1e-6, "symmetric lights")
end)

T.test("a point in shadow gets exactly the ambient term ka*C*Ia", function()
  local scene = lancer.scene{ambient = 0.2, camera = lancer.camera{
    from = {8, 3, 0}, at = {0, 0, 0}, fov = 20}}
  scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                         material = lancer.material{color = 0.5}})
  -- The quad at y = 5 hides the light at y = 9 from the square |x|, |z| < 1.8
  -- of the plane; the camera looks at (0, 0, 0) from the side, under it.
  scene:add(lancer.quad{corner = {-1, 5, -1}, u = {2, 0, 0}, v = {0, 0, 2}})
  scene:add(lancer.point_light{position = {0, 9, 0}, intensity = 81})
  local img, stats = scene:render{width = 9, height = 9}
  -- Pixels are single floats: 0.1 is exact to float rounding, 2^-24 relative.
  T.near(select(1, img:pixel(5, 5)), 0.5 * 0.2, 0.1 * 2 ^ -23, "shadowed centre: ambient only")
  local r = img:pixel(5, 9)          -- bottom row: the plane near the camera, lit
  assert(r > 0.5 * 0.2 + 0.01, "near plane is lit: " .. r)
  T.eq(stats.effects.ambient, true, "ambient effect")
end)

T.test("facing mirrors: geometric series to max_depth, W*H*depth reflection rays", function()
  for _, depth in ipairs{0, 1, 3, 5} do
    local e, kr = 0.1, 0.5
    local m = lancer.material{kd = 0, kr = kr, emission = e}
    local scene = lancer.scene{max_depth = depth, camera = lancer.camera{
      from = {0, 0, -0.5}, at = {0, 0, 1}, fov = 10}}
    scene:add(lancer.quad{corner = {-10, -10, 1}, u = {20, 0, 0}, v = {0, 20, 0}, material = m})
    scene:add(lancer.quad{corner = {-10, -10, -1}, u = {20, 0, 0}, v = {0, 20, 0}, material = m})
    local img, stats = scene:render{width = 8, height = 6}
    local expected = 0
    for k = 0, depth do expected = expected + e * kr ^ k end
    assert_close(img, function() return expected, expected, expected end, 1e-5,
                 "depth " .. depth)
    T.eq(stats.rays.reflection, 8 * 6 * depth, "reflection rays at depth " .. depth)
    T.eq(stats.effects.reflect, depth > 0, "reflect effect")
  end
end)

T.test("Phong highlight: ks*(R.V)^alpha*I/d^2 with absorb='diffuse'", function()
  local h, I = 4, 16
  local scene = lancer.scene{camera = lancer.camera{from = {0, h, 0}, at = {0, 0, 0},
                                                    up = {0, 0, 1}, fov = 1}}
  local m = lancer.material{color = {0.2, 0.4, 0.6}, kd = 0.5, ks = 0.7, alpha = 20,
                            absorb = "diffuse"}
  scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}, material = m})
  scene:add(lancer.point_light{position = {0, h, 0}, intensity = I})
  local img = scene:render{width = 1, height = 1}
  local r, g, b = img:pixel(1, 1)
  local lc = I / h ^ 2
  T.near(r, 0.2 * 0.5 * lc + 0.7 * lc, 1e-6, "red")
  T.near(g, 0.4 * 0.5 * lc + 0.7 * lc, 1e-6, "green")
  T.near(b, 0.6 * 0.5 * lc + 0.7 * lc, 1e-6, "blue")
end)

T.test("absorb='all' multiplies the whole sum by the colour (the seed)", function()
  local h, I = 4, 16
  local scene = lancer.scene{camera = lancer.camera{from = {0, h, 0}, at = {0, 0, 0},
                                                    up = {0, 0, 1}, fov = 1}}
  local m = lancer.material{color = {0.2, 0.4, 0.6}, kd = 0.5, ks = 0.7, alpha = 20}
  scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}, material = m})
  scene:add(lancer.point_light{position = {0, h, 0}, intensity = I})
  local r, g, b = scene:render{width = 1, height = 1}:pixel(1, 1)
  local lc = I / h ^ 2
  T.near(r, 0.2 * (0.5 + 0.7) * lc, 1e-6, "red")
  T.near(b, 0.6 * (0.5 + 0.7) * lc, 1e-6, "blue")
end)

T.test("light_samples = 0: an emissive sphere lights by pi*L*(r/d)^2 toward its centre", function()
  local r, d, L, kd = 0.5, 4, 10, 0.9
  local scene = lancer.scene{camera = lancer.camera{from = {0, 2, 0.001}, at = {0, 0, 0},
                                                    up = {0, 0, 1}, fov = 0.5}}
  scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                         material = lancer.material{kd = kd}})
  scene:add(lancer.sphere{center = {0, d, 0}, radius = r,
                          material = lancer.material{kd = 0, emission = L}})
  local img, stats = scene:render{width = 1, height = 1, light_samples = 0}
  -- The camera looks down at the plane near (0, 0, 0), straight under the light.
  T.near(select(1, img:pixel(1, 1)), kd * L * (r / d) ^ 2, 1e-4, "plane under the light")
  T.eq(stats.effects.emitter, true, "emitter effect")
  T.eq(stats.rays.shadow, 1, "one shadow ray toward the light's centre")
end)

T.test("cosine = false drops n.l (the seed's figure 7)", function()
  local scene = lancer.scene{camera = lancer.camera{from = {0, 2, 0}, at = {0, 0, 0},
                                                    up = {0, 0, 1}, fov = 1}}
  scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}})
  scene:add(lancer.point_light{position = {3, 4, 0}, intensity = 25})
  local with = scene:render{width = 1, height = 1}:pixel(1, 1)
  local without = scene:render{width = 1, height = 1, cosine = false}:pixel(1, 1)
  T.near(with, 1 * 0.8, 1e-6, "with n.l = 4/5")
  T.near(without, 1, 1e-6, "without")
end)

T.test("falloff = 'none': the light's colour times n.l, whatever the distance", function()
  local scene = lancer.scene{camera = lancer.camera{from = {0, 2, 0}, at = {0, 0, 0},
                                                    up = {0, 0, 1}, fov = 1}}
  scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}})
  scene:add(lancer.point_light{position = {0, 100, 0}, color = {0.7, 0.7, 0.7},
                               falloff = "none"})
  T.near(scene:render{width = 1, height = 1}:pixel(1, 1), 0.7, 1e-6, "no falloff")
end)

T.test("a scene without lights spawns no shadow ray", function()
  local scene = lancer.scene{ambient = 0.5, camera = lancer.camera{from = {0, 0, -4}, at = {0, 0, 0}}}
  scene:add(lancer.sphere{center = {0, 0, 0}, radius = 1, material = lancer.material{ks = 1}})
  local img, stats = scene:render{width = 16, height = 12}
  T.eq(stats.rays.shadow, 0, "shadow rays")
  T.eq(stats.effects.shadow, false, "shadow effect")
  T.eq(stats.effects.specular, false, "specular needs a light")
  T.eq(select(1, img:pixel(8, 6)), 0.5, "ambient only")
end)

T.test("samples: W*H*spp camera rays; images identical across runs and threads", function()
  local scene = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 0.5, 0}}}
  scene:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}})
  scene:add(lancer.sphere{center = {0, 1, 0}, radius = 1,
                          material = lancer.material{kr = 0.5, kd = 0.5}})
  scene:add(lancer.point_light{position = {2, 4, -2}, intensity = 20})
  local a, sa = scene:render{width = 37, height = 23, samples = 4, threads = 1}
  local b = scene:render{width = 37, height = 23, samples = 4, threads = 2}
  local c = scene:render{width = 37, height = 23, samples = 4, threads = 3}
  T.eq(sa.rays.camera, 37 * 23 * 4, "camera rays")
  for y = 1, 23 do
    for x = 1, 37 do
      local r1, g1, b1 = a:pixel(x, y)
      local r2, g2, b2 = b:pixel(x, y)
      local r3, g3, b3 = c:pixel(x, y)
      assert(r1 == r2 and g1 == g2 and b1 == b2 and r1 == r3 and g1 == g3 and b1 == b3,
             ("pixel %d,%d differs between thread counts"):format(x, y))
    end
  end
  local d = scene:render{width = 37, height = 23, samples = 4, seed = 7}
  local differ = 0
  for y = 1, 23 do
    for x = 1, 37 do
      if a:pixel(x, y) ~= d:pixel(x, y) then differ = differ + 1 end
    end
  end
  assert(differ > 0, "another seed must give another sampling")
end)

T.test("saved PNG: gAMA 1.0 when linear, an sRGB chunk by default", function()
  local dir = os.tmpname()
  os.remove(dir)
  local scene = lancer.scene{background = {0.25, 0.5, 1}, camera = lancer.camera{
    from = {0, 0, 0}, at = {0, 0, 1}}}
  local img = scene:render{width = 4, height = 2}
  img:save(dir .. ".png", {encoding = "linear"})
  local bytes = T.slurp(dir .. ".png")
  os.remove(dir .. ".png")
  assert(bytes:sub(1, 8) == "\137PNG\r\n\26\n", "PNG signature")
  assert(bytes:find("gAMA", 1, true), "linear files carry gAMA 1.0")
  img:save(dir .. ".png")
  bytes = T.slurp(dir .. ".png")
  os.remove(dir .. ".png")
  assert(bytes:find("sRGB", 1, true), "sRGB files carry the sRGB chunk")
end)

T.test("cutoff: bounces weighing under 1/255 are not traced, and counted", function()
  local e, kr = 0.1, 0.5
  local m = lancer.material{kd = 0, kr = kr, emission = e}
  local scene = lancer.scene{max_depth = 20, camera = lancer.camera{
    from = {0, 0, -0.5}, at = {0, 0, 1}, fov = 10}}
  scene:add(lancer.quad{corner = {-10, -10, 1}, u = {20, 0, 0}, v = {0, 20, 0}, material = m})
  scene:add(lancer.quad{corner = {-10, -10, -1}, u = {20, 0, 0}, v = {0, 20, 0}, material = m})
  -- Weight after k bounces is 0.5^k: 0.5^7 >= 1/255 > 0.5^8, so 7 are traced.
  local img, st = scene:render{width = 4, height = 3}
  T.eq(st.rays.reflection, 4 * 3 * 7, "reflections traced")
  T.eq(st.rays.cut, 4 * 3, "one cut per pixel")
  local full, sf = scene:render{width = 4, height = 3, cutoff = 0}
  T.eq(sf.rays.reflection, 4 * 3 * 20, "cutoff = 0 traces to max_depth")
  T.eq(sf.rays.cut, 0, "nothing cut")
  -- What is lost is the series' tail: e * sum_{k >= 8} 0.5^k = e * 0.5^7.
  T.near(full:pixel(2, 2) - img:pixel(2, 2), e * (0.5 ^ 8 - 0.5 ^ 21) / (1 - 0.5), 1e-6,
         "energy lost")
  T.eq(st.self_hits, 0, "no ray re-hit the mirror it left")
end)
