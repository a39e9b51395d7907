-- test_glass.lua: dielectrics (kt, ior, fresnel, absorption, shadow): the
-- closed forms of issue 12 (a slab seen head-on, a ray through a sphere's
-- centre, a ball lens's focus, filtered shadows), the ray tree's counts,
-- and effects on demand. The docs/numerics.md cases (H18-H21, A4, A5) are in
-- test_hard.lua.
local T = require "harness"
local lancer = require "lancer"
local O = require "optics"

local glass, glow, fresnel, chain = O.glass, O.glow, O.fresnel, O.chain

local function sub(a, b) return {a[1] - b[1], a[2] - b[2], a[3] - b[3]} end
local function dot(a, b) return a[1] * b[1] + a[2] * b[2] + a[3] * b[3] end
local function len(a) return math.sqrt(dot(a, a)) end

-- The centre pixel of an odd-sized image: its ray goes exactly down the axis.
local function centre(img) return img:pixel((img.width + 1) // 2, (img.height + 1) // 2) end

-- A slab of glass 0.5 thick across the axis, z in [0, 0.5], before a panel
-- of radiance L at z = 3; the camera far down -z; black elsewhere.
local function slab_scene(m, L)
  local s = lancer.scene{camera = O.far_camera(0.3)}
  s:add(lancer.box{min = {-2, -2, 0}, max = {2, 2, 0.5}, material = m})
  s:add(lancer.quad{corner = {-5, -5, 3}, u = {10, 0, 0}, v = {0, 10, 0}, material = glow(L)})
  return s
end

T.test("a slab head-on: L (1 - R)^2 sum R^2k to the depth traced, (1 - R) / (1 + R) deep",
       function()
  local L, R = 0.8, fresnel(1, 1.5)
  local s = slab_scene(glass(), L)
  for _, depth in ipairs{1, 2, 3, 4, 6, 10, 30} do
    local img, st = s:render{width = 5, height = 5, max_depth = depth, cutoff = 0}
    local want = 0
    for k = 0, (depth - 2) // 2 do want = want + L * (1 - R) ^ 2 * R ^ (2 * k) end
    T.near(centre(img), want, 1e-6, ("max_depth %d"):format(depth))
    T.near(centre(img), chain({{1.5, 0.5}, {1 / 1.5, 0}}, depth, L, 0), 1e-6, "the chain")
    T.eq(T.bad_pixels(img), 0, "NaN or infinite pixels")
    if depth == 1 then T.eq(st.rays.refraction, 25, "depth 1: one refraction per pixel") end
  end
  local deep = s:render{width = 5, height = 5, max_depth = 30, cutoff = 0}
  T.near(centre(deep), L * (1 - R) ^ 2 / (1 - R * R), 1e-6, "the whole series")
  T.near(L * (1 - R) ^ 2 / (1 - R * R), L * (1 - R) / (1 + R), 1e-15, "(1 - R) / (1 + R)")
  -- the default cutoff stops at T^2 R^2 L = 0.0012 < 1/255
  local cut, st = s:render{width = 5, height = 5, max_depth = 30}
  T.near(centre(cut), L * (1 - R) ^ 2, 1e-6, "the default cutoff's truncation")
  assert(st.rays.cut > 0, "cut branches are counted")
end)

T.test("a slab with absorption: each crossing of its thickness d keeps e^(-sigma d)",
       function()
  local L, R, d = 1, fresnel(1, 1.5), 0.5
  local sigma = {0.2, 0.9, 2.5}
  local s = slab_scene(glass{absorption = sigma}, L)
  for _, depth in ipairs{2, 4, 8, 20} do
    local img = s:render{width = 5, height = 5, max_depth = depth, cutoff = 0}
    local r, g, b = centre(img)
    for i, got in ipairs{r, g, b} do
      local want = 0
      for k = 0, (depth - 2) // 2 do
        want = want + L * (1 - R) ^ 2 * R ^ (2 * k) * math.exp(-sigma[i] * d * (2 * k + 1))
      end
      T.near(got, want, 1e-6, ("max_depth %d, channel %d"):format(depth, i))
      T.near(got, chain({{1.5, d, sigma[i]}, {1 / 1.5, 0}}, depth, L, 0), 1e-6, "chain")
    end
  end
  -- transmittance = {colour, distance} is the same absorption
  local m = glass{transmittance = {{math.exp(-0.2 * 2), math.exp(-0.9 * 2),
                                    math.exp(-2.5 * 2)}, 2}}
  for i, a in ipairs(m.absorption) do T.near(a, sigma[i], 1e-15, "absorption " .. i) end
end)

T.test("glass without Fresnel: the seed's fixed kr and kt", function()
  local L, kr, kt = 1, 0.1, 0.7
  local s = slab_scene(glass{kr = kr, kt = kt, fresnel = false}, L)
  for _, depth in ipairs{2, 4, 6} do
    local img = s:render{width = 5, height = 5, max_depth = depth, cutoff = 0}
    local want = 0
    for k = 0, (depth - 2) // 2 do want = want + L * kt * kt * kr ^ (2 * k) end
    T.near(centre(img), want, 1e-6, ("max_depth %d"):format(depth))
  end
end)

T.test("a ray through a sphere's centre is not deflected, nor is a ray through ior 1",
       function()
  for _, ior in ipairs{1.5, 2.4, 1} do
    local s = lancer.scene{camera = lancer.camera{from = {0.3, -0.2, -5}, at = {0, 0, 0}}}
    s:add(lancer.sphere{center = {0, 0, 0}, radius = 1, material = glass{ior = ior}})
    local tree = s:explain{x = 17, y = 13, width = 33, height = 25, max_depth = 4,
                           cutoff = 0}
    -- in, out, and back and forth along the diameter after internal
    -- reflections: every refracted ray along it, one way or the other
    local d0 = tree.direction
    local through = 0
    for _, r in ipairs(O.records(tree)) do
      if r.kind == "refraction" then
        through = through + 1
        local k = dot(r.direction, d0) > 0 and 1 or -1
        local off = len(sub(r.direction, {k * d0[1], k * d0[2], k * d0[3]}))
        assert(off <= 1e-12, ("ior %g: refracted off by %g"):format(ior, off))
      end
    end
    -- ior 1 reflects nothing: in and out only
    T.eq(through, ior == 1 and 2 or 4, "in, out, and out both ways after reflections inside")
  end
end)

T.test("a ball lens focuses a parallel beam at n R / (2 (n - 1)) from its centre", function()
  -- A beam at height h crosses the axis at f, less the ball's spherical
  -- aberration, 5/12 h^2 / R (n = 1.5, f = 1.5 R), plus f^2 / D: the beam
  -- comes from a camera D = 1e7 away, not from infinity.
  local n, R, D = 1.5, 1, 1e7
  local f = n * R / (2 * (n - 1))
  local s = lancer.scene{camera = O.far_camera(0.1, D)}
  s:add(lancer.sphere{center = {0, 0, 0}, radius = R, material = glass{ior = n}})
  local W = 101
  for _, i in ipairs{52, 56, 61, 76, 101} do
    local tree = s:explain{x = i, y = 51, width = W, height = W, max_depth = 2}
    local inside
    for _, r in ipairs(tree.rays) do if r.kind == "refraction" then inside = r end end
    local out
    for _, r in ipairs(inside.rays) do if r.kind == "refraction" then out = r end end
    local h = math.abs(inside.origin[1])
    local o, d = out.origin, out.direction
    assert(math.abs(o[2]) < 1e-12 and math.abs(d[2]) < 1e-12, "in the plane y = 0")
    local z = o[3] - o[1] * d[3] / d[1]            -- where it crosses x = 0
    local aberration, want = 5 / 12 * h * h / R, f + f * f / D - 5 / 12 * h * h / R
    assert(math.abs(z - want) <= 0.01 * aberration + 1e-9,
           ("h = %.4g: crosses at %.9g, f = %g, expected %.9g"):format(h, z, f, want))
  end
  -- Reversed: from its focus, the ball sends a parallel beam, so a disc of
  -- radius a in front of it looks the same size (a / f) at any distance;
  -- 1 % off the focus, the far one does not.
  local a, W2, half = 0.01, 41, 0.008
  local function disc_radius(camz, D)
    local sc = lancer.scene{camera = lancer.camera{from = {0, 0, camz}, at = {0, 0, -1},
                                                   fov = 2 * math.deg(math.atan(half))}}
    sc:add(lancer.sphere{center = {0, 0, 0}, radius = R, material = glass{ior = n}})
    local seg = 64
    local verts, faces = {{0, 0, -D}}, {}
    for k = 0, seg - 1 do
      local t = 2 * math.pi * k / seg
      verts[#verts + 1] = {a * math.cos(t) / math.cos(math.pi / seg),
                           a * math.sin(t) / math.cos(math.pi / seg), -D}
      faces[#faces + 1] = {1, 2 + k, 2 + (k + 1) % seg}
    end
    sc:add(lancer.mesh{vertices = verts, faces = faces, material = glow(1)})
    local img = sc:render{width = W2, height = W2, max_depth = 4}
    local lit = 0
    for x = 1, W2 do if img:pixel(x, (W2 + 1) // 2) > 0.5 then lit = lit + 1 end end
    return lit / 2
  end
  local want = (W2 / 2) * (a / f) / half            -- paraxial, in pixels
  for _, D in ipairs{100, 1000} do
    local r = disc_radius(f, D)
    assert(math.abs(r - want) <= 1, ("from the focus, the disc %g away spans %g pixels, "
      .. "not %.2f"):format(D, r, want))
  end
  local off = disc_radius(1.01 * f, 1000)
  assert(math.abs(off - want) > 3, "1 % off the focus the far disc spans " .. off)
end)

T.test("filtered shadows: a floor under a glass slab gets the light times T^2 e^(-sigma d)",
       function()
  -- A point light 4 above a white floor; a slab 0.2 thick at y = 1 covers
  -- x, z in [-1, 1]. The camera, low, sees the floor under it from the side.
  local I, thick, sigma = 16, 0.2, 0.5
  local function scene(m)
    local s = lancer.scene{camera = lancer.camera{from = {0, 0.5, -3}, at = {0, 0, 0},
                                                  fov = 40}}
    s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                       material = lancer.material{ka = 0}})
    s:add(lancer.box{min = {-1, 1, -1}, max = {1, 1 + thick, 1}, material = m})
    s:add(lancer.point_light{position = {0, 4, 0}, intensity = I})
    return s
  end
  local W, H = 40, 30
  local cam = {from = {0, 0.5, -3}, at = {0, 0, 0}, fov = 40}
  local function each_floor_pixel(fn)
    -- the camera model of the README (test_hard.lua's frame and pixel_ray)
    local function norm(v) local l = len(v) return {v[1] / l, v[2] / l, v[3] / l} end
    local f = norm(sub(cam.at, cam.from))
    local r = norm({f[3], 0, -f[1]})                 -- f x up, up = +y
    r = {-r[1], -r[2], -r[3]}
    local u = {r[2] * f[3] - r[3] * f[2], r[3] * f[1] - r[1] * f[3], r[1] * f[2] - r[2] * f[1]}
    local tx = math.tan(math.rad(cam.fov) / 2)
    local ty = tx * H / W
    for j = 0, H - 1 do
      for i = 0, W - 1 do
        local sx, sy = (2 * (i + 0.5) / W - 1) * tx, (1 - 2 * (j + 0.5) / H) * ty
        local d = norm{f[1] + r[1] * sx + u[1] * sy, f[2] + r[2] * sx + u[2] * sy,
                       f[3] + r[3] * sx + u[3] * sy}
        if d[2] < 0 then
          local t = -cam.from[2] / d[2]
          local p = {cam.from[1] + d[1] * t, 0, cam.from[3] + d[3] * t}
          local tl = sub({0, 4, 0}, p)
          local dist = len(tl)
          local l = {tl[1] / dist, tl[2] / dist, tl[3] / dist}
          -- where the shadow ray crosses the slab's faces, y = 1 and 1.2:
          -- under it (through both), clear of it, or through a side (left out)
          local function at(y) return {p[1] + l[1] * y / l[2], p[3] + l[3] * y / l[2]} end
          local function inside(q, m) return math.abs(q[1]) < m and math.abs(q[2]) < m end
          local q0, q1 = at(1), at(1 + thick)
          local under = inside(q0, 0.999) and inside(q1, 0.999)
          -- the slab is convex: outside past the same edge at both heights
          local function past(k, m) return q0[k] * m > 1.001 and q1[k] * m > 1.001 end
          local clear = past(1, 1) or past(1, -1) or past(2, 1) or past(2, -1)
          if under or clear then fn(i + 1, j + 1, I * l[2] / (dist * dist), under, l[2]) end
        end
      end
    end
  end
  local img, st = scene(glass{absorption = sigma}):render{width = W, height = H}
  assert(st.effects.filter and st.effects.refract, "filter and refract effects")
  local n = 0
  each_floor_pixel(function(x, y, lit, under, c)
    -- the shadow ray goes straight: in and out at cos c, 0.2 / c inside
    local T2 = (1 - fresnel(c, 1.5)) ^ 2
    local want = under and lit * T2 * math.exp(-sigma * thick / c) or lit
    T.near(img:pixel(x, y), want, 1e-5 * want, ("pixel (%d, %d)"):format(x, y))
    if under then n = n + 1 end
  end)
  assert(n > 50, "pixels under the slab: " .. n)
  -- fixed kt without Fresnel: kt^2; 'opaque': the seed's black shadow
  local fixed = scene(glass{kt = 0.8, fresnel = false}):render{width = W, height = H}
  local opaque, so = scene(glass{shadow = "opaque"}):render{width = W, height = H}
  T.eq(so.effects.filter, false, "no filter effect when every glass is opaque")
  each_floor_pixel(function(x, y, lit, under)
    T.near(fixed:pixel(x, y), under and lit * 0.64 or lit, 1e-5 * lit, "kt^2")
    T.near(opaque:pixel(x, y), under and 0 or lit, 1e-5 * lit, "opaque")
  end)
end)

T.test("the ray tree: max_depth counts every bounce, reflection or refraction", function()
  -- One ray down the axis of a glass sphere under a uniform sky, cutoff 0:
  -- each hit inside sends one ray out and one back, one deeper each time.
  local s = lancer.scene{camera = O.far_camera(0.5), background = 1}
  s:add(lancer.sphere{center = {0, 0, 0}, radius = 1, material = glass()})
  for _, depth in ipairs{0, 1, 2, 5, 9} do
    local _, st = s:render{width = 1, height = 1, max_depth = depth, cutoff = 0}
    T.eq(st.rays.reflection, depth, ("reflection rays at max_depth %d"):format(depth))
    T.eq(st.rays.refraction, depth, ("refraction rays at max_depth %d"):format(depth))
    T.eq(st.rays.cut, 0, "nothing cut")
  end
  -- explain shows them, and the tree adds up to the pixel
  local img = s:render{width = 1, height = 1, max_depth = 5, cutoff = 0}
  local tree = s:explain{x = 1, y = 1, width = 1, height = 1, max_depth = 5, cutoff = 0}
  local kinds = {}
  for _, r in ipairs(O.records(tree)) do kinds[r.kind] = (kinds[r.kind] or 0) + 1 end
  T.eq(kinds.refraction, 5, "refraction records")
  T.eq(kinds.reflection, 5, "reflection records")
  T.near(tree.contribution[1], img:pixel(1, 1), 1e-6, "the tree adds up to the pixel")
  assert(tostring(tree):find("refraction hits sphere 1", 1, true), tostring(tree))
end)

T.test("effects on demand: no transmissive material in use, no refraction at all", function()
  local function scene(extra)
    local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 0.5, 0}}}
    s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}})
    s:add(lancer.sphere{center = {0, 1, 0}, radius = 1, material = lancer.material{kr = 0.5}})
    s:add(lancer.point_light{position = {2, 4, -3}, intensity = 20})
    if extra then extra(s) end
    return s
  end
  local o = {width = 32, height = 24}
  local plain, st = scene():render(o)
  T.eq(st.rays.refraction, 0, "refraction rays")
  T.eq(st.effects.refract, false, "refract effect")
  T.eq(st.effects.filter, false, "filter effect")
  T.eq(st.why.refract, "no material in use has kt > 0", "why")
  -- a glass defined but not used changes nothing, bit for bit
  local unused = glass()
  local same, su = scene(function() local _ = unused end):render(o)
  T.eq(same:diff(plain, 0).max, 0, "image")
  T.eq(su.rays.refraction, 0, "refraction rays")
  -- in use: on, and said why; max_depth 0 turns it off
  local _, sg = scene(function(s)
    s:add(lancer.sphere{center = {1.5, 0.5, -1}, radius = 0.5, material = unused})
  end):render(o)
  assert(sg.effects.refract and sg.rays.refraction > 0, "refraction with glass")
  T.eq(sg.why.refract, "1 material in use with kt > 0 (first: #3), max_depth 3", "why")
  assert(sg.effects.filter, "filtered shadows")
  local _, s0 = scene(function(s)
    s:add(lancer.sphere{center = {1.5, 0.5, -1}, radius = 0.5, material = unused})
  end):render{width = 32, height = 24, max_depth = 0}
  T.eq(s0.effects.refract, false, "max_depth 0")
  T.eq(s0.why.refract, "max_depth is 0", "why at depth 0")
  T.eq(s0.rays.refraction, 0, "no refraction ray at depth 0")
  -- the ledger has their rows
  local text = lancer.ledger(sg)
  assert(text:find("refraction %d+") and text:find("on  refract ") and
         text:find("on  filter "), text)
end)

T.test("S10 with glass: the planned shading equals the generic path, bit for bit", function()
  local s = lancer.scene{camera = lancer.camera{from = {0, 1.5, -5}, at = {0, 0.7, 0}},
                         ambient = 0.05, background = {0.1, 0.2, 0.3}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                     material = lancer.material{color = 0.7, kr = 0.2}})
  s:add(lancer.sphere{center = {-0.8, 1, 0}, radius = 1, material = glass{ks = 0.5,
                      absorption = {0.1, 0.3, 0.2}}})
  s:add(lancer.sphere{center = {-0.8, 1, 0}, radius = 0.4, material = glass{ior = 1}})
  s:add(lancer.box{min = {0.5, 0, -0.5}, max = {1.5, 1, 0.5},
                   material = glass{color = {0.9, 0.8, 1}, ior = 1.33, kr = 0.05}})
  s:add(lancer.sphere{center = {1.5, 0.4, -1.4}, radius = 0.4,
                      material = lancer.material{kr = 0.3, glossiness = 8, kd = 0.5}})
  s:add(lancer.sphere{center = {-2, 3, -1}, radius = 0.3,
                      material = lancer.material{kd = 0, emission = 20}})
  s:add(lancer.point_light{position = {3, 5, -3}, intensity = 40})
  for _, opts in ipairs{{samples = 2}, {samples = 1, cutoff = 0, max_depth = 6},
                        {samples = 1, light_samples = 0}} do
    opts.width, opts.height = 32, 24
    local a = s:render(opts)
    opts.generic = true
    local b = s:render(opts)
    T.eq(b:diff(a, 0).max, 0, "generic path")
    T.eq(T.bad_pixels(a), 0, "NaN or infinite pixels")
  end
end)

T.test("materials: the dielectric's fields read back; the defaults print as before", function()
  local m = lancer.material{kd = 0, kt = 0.9, ior = 1.33, fresnel = false,
                            absorption = {0.1, 0.2, 0.3}, shadow = "opaque"}
  T.eq(m.kt, 0.9, "kt")
  T.eq(m.ior, 1.33, "ior")
  T.eq(m.fresnel, false, "fresnel")
  T.eq(m.shadow, "opaque", "shadow")
  T.eq(m.absorption[3], 0.3, "absorption")
  local d = lancer.material{}
  T.eq(d.kt, 0, "kt default")
  T.eq(d.ior, 1, "ior default")
  T.eq(d.fresnel, true, "fresnel default")
  T.eq(d.shadow, "filtered", "shadow default")
  T.eq(d.absorption[1] + d.absorption[2] + d.absorption[3], 0, "absorption default")
  assert(not tostring(d):find("kt"), tostring(d))
  local text = tostring(m)
  assert(text:find("kt = 0.9, ior = 1.33, fresnel = false, absorption = {0.1, 0.2, 0.3}, "
                   .. "shadow = 'opaque'}", 1, true), text)
  -- what it prints makes the same material
  local again = load("local lancer = require 'lancer' return " .. text)()
  T.eq(tostring(again), text, "round trip")
end)

T.test("a scaled glass scene keeps its absorption per length: the same picture", function()
  local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 0.5, 0}}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}})
  s:add(lancer.sphere{center = {0, 1, 0}, radius = 1,
                      material = glass{absorption = {0.5, 1, 2}}})
  s:add(lancer.point_light{position = {2, 4, -3}, intensity = 20})
  local o = {width = 48, height = 36, max_depth = 8}
  local ref = s:render(o)
  for _, k in ipairs{1e-3, 1e3} do
    local img = s:transformed(k):render(o)
    local d = img:diff(ref, 1 / 255)
    assert(d.within >= 0.999, ("scale %g: %.4f within 1/255"):format(k, d.within))
  end
end)

local function script(text)
  local dir = T.temp_dir()
  T.write(dir .. "/glass.lua", text)
  return dir, dir .. "/glass.lua"
end

local GLASS_SCENE = [[
local lancer = require "lancer"
local glass = lancer.material{kd = 0, ka = 0, kt = 1, ior = 1.5, ks = 0.5,
                              absorption = {0.05, 0.1, 0.2}}
local s = lancer.scene{camera = lancer.camera{from = {0, 1.2, -4}, at = {0, 0.6, 0}},
                       background = {0.3, 0.4, 0.6}}
s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}})
s:add(lancer.sphere{center = {-0.6, 0.8, 0}, radius = 0.8, material = glass})
s:add(lancer.box{min = {0.4, 0, -0.4}, max = {1.4, 0.6, 0.4}, material = glass})
s:add(lancer.sphere{center = {1.6, 0.4, 1}, radius = 0.4,
                    material = lancer.material{kr = 0.8, kd = 0.2}})
s:add(lancer.point_light{position = {2, 4, -3}, intensity = 25})
s:render{width = 96, height = 72, max_depth = 10}
]]

T.test("H1/H2 with glass: lancer --check finds the glass scene stable", function()
  local dir, path = script(GLASS_SCENE)
  local _, err, code = T.run(T.lancer .. " --check " .. T.quote(path))
  os.execute("rm -rf " .. T.quote(dir))
  T.eq(code, 0, "exit status; stderr: " .. err)
  local n = 0
  for pct in err:gmatch("(%d+%.%d+) %% of pixels within 1/255") do
    assert(tonumber(pct) >= 99.9, "a variant differs: " .. err)
    n = n + 1
  end
  T.eq(n, 3, "three variants")
  assert(err:find("0 of 1 renders unstable", 1, true), err)
end)

T.test("--accuracy --knob max_depth on glass: the error falls with depth", function()
  local dir, path = script(GLASS_SCENE)
  local out, err, code = T.run(("%s --accuracy --knob max_depth=1,2,4,8 --seeds 2 --out %s %s")
    :format(T.quote(T.lancer), T.quote(dir), T.quote(path)))
  T.eq(code, 0, "exit status; stderr: " .. err)
  local rmse = {}
  for level, e in out:gmatch("\n%s*(%d+)%s+[%d.]+%s+%d+%s+([%d.e+-]+)") do
    rmse[#rmse + 1] = tonumber(e)
  end
  T.eq(#rmse, 4, "a row per level:\n" .. out)
  for i = 2, 4 do
    assert(rmse[i] < rmse[i - 1], "the error falls with depth:\n" .. out)
  end
  local f = io.open(dir .. "/glass-max_depth-runs.csv")
  local head = f:read("l")
  f:close()
  assert(head:find("refraction", 1, true), head)
  os.execute("rm -rf " .. T.quote(dir))
end)
