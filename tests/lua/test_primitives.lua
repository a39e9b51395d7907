-- test_primitives.lua: discs, cylinders, cones, tori and ellipsoids in scenes:
-- scale and translation invariance with every one of them (mirrors and area
-- lights included), their area lights against closed forms, listing,
-- removing, explain's names, and every validation rule naming its field.
local T = require "harness"
local lancer = require "lancer"

local HERE = "test_primitives.lua:"

local function no_bad(img, what)
  T.eq(T.bad_pixels(img), 0, what .. ": NaN or infinite channels")
end

-- Every new kind, placed and moved (a sheared torus, a stretched sphere),
-- a mirror cylinder, a glowing cone and disc, at scale s moved by (T, T/2, T/3).
local function scene_at(s, T)
  local function P(p) return {p[1] * s + T, p[2] * s + T / 2, p[3] * s + T / 3} end
  local function V(v) return {v[1] * s, v[2] * s, v[3] * s} end
  local sc = lancer.scene{camera = lancer.camera{from = P{0, 2.5, -7}, at = P{0, 0.8, 0},
                                                 fov = 55},
                          ambient = 0.05, background = {0.1, 0.15, 0.3}}
  local m = function(c) return lancer.material{color = c, ks = 0.3, alpha = 30} end
  sc:add(lancer.plane{point = P{0, 0, 0}, normal = {0, 1, 0}, material = m{0.8, 0.8, 0.7}})
  sc:add(lancer.cylinder{base = P{-2.5, 0, 0}, axis = V{0, 1.6, 0.2}, radius = 0.5 * s,
                         material = lancer.material{kd = 0.2, kr = 0.7}})
  sc:add(lancer.cone{base = P{-1, 0, 0.5}, top = P{-0.8, 1.8, 0.4}, base_radius = 0.6 * s,
                     top_radius = 0.1 * s, material = m{0.3, 0.5, 0.9}})
  sc:add(lancer.torus{center = P{0.8, 0.35, -0.5}, axis = {0.2, 1, -0.3}, major = 0.6 * s,
                      minor = 0.2 * s, material = m{0.3, 0.9, 0.3}})
  sc:add(lancer.ellipsoid{center = P{2.3, 0.8, 0.3}, radii = V{0.5, 0.8, 0.4},
                          material = m{0.9, 0.4, 0.2}})
  sc:add(lancer.disc{center = P{0, 0.01, -1.8}, normal = {0, 1, 0}, radius = 0.5 * s,
                     inner_radius = 0.2 * s, material = m{0.9, 0.9, 0.2}})
  local sheared = lancer.translate(P{-0.3, 0.3, -2.5}) * lancer.scale(s) *
                  lancer.transform{{1, 0.4, 0, 0}, {0, 1, 0, 0}, {0, 0.3, 1.5, 0}}
  sc:add(lancer.torus{center = {0, 0, 0}, axis = {0, 1, 0}, major = 0.4, minor = 0.1,
                      material = m{0.8, 0.3, 0.8}}:moved(sheared))
  sc:add(lancer.sphere{center = {0, 0, 0}, radius = 0.3, material = m{0.6, 0.6, 0.9}}:moved(
    lancer.translate(P{1.5, 1.8, 1}) * lancer.scale(s) * lancer.scale(1.6, 0.7, 1)))
  sc:add(lancer.cone{base = P{-2, 3, 1.5}, top = P{-2, 3.4, 1.5}, base_radius = 0.3 * s,
                     top_radius = 0, material = lancer.material{kd = 0, emission = 20}})
  sc:add(lancer.disc{center = P{1.5, 3.5, -1}, normal = {0, -1, 0.2}, radius = 0.4 * s,
                     material = lancer.material{kd = 0, emission = 15}})
  sc:add(lancer.point_light{position = P{3, 5, -4}, intensity = 30 * s * s})
  return sc
end

local OPTS = {width = 64, height = 48, samples = 16, seed = 5, light_samples = 4}
local ref_image, ref_stats

local function reference()
  if not ref_image then
    ref_image, ref_stats = scene_at(1, 0):render(OPTS)
    no_bad(ref_image, "scale 1")
  end
  return ref_image
end

local function invariance(s, shift, what)
  local img, st = scene_at(s, shift):render(OPTS)
  no_bad(img, what)
  T.eq(st.self_hits, 0, what .. ": self-hits")
  local d = img:diff(reference(), 1 / 255)
  assert(d.within >= 0.999, ("%s: only %.3f%% of pixels within 1/255 (worst %g at %d, %d)")
         :format(what, 100 * d.within, d.max, d.worst_x, d.worst_y))
end

T.test("H1 with every new shape: scale 1e-4..1e6, >= 99.9% within 1/255, no self-hit", function()
  reference()
  T.eq(ref_stats.self_hits, 0, "self-hits at scale 1")
  assert(ref_stats.rays.reflection > 0 and ref_stats.rays.light > 0, "mirrors and lights")
  for _, s in ipairs{1e-4, 1e-2, 1e2, 1e4, 1e6} do
    invariance(s, 0, ("scale %g"):format(s))
  end
end)

T.test("H2 with every new shape: moved 1e3..1e7", function()
  for _, shift in ipairs{1e3, 1e5, 1e7} do
    invariance(1, shift, ("moved %g"):format(shift))
  end
end)

-- ---- area lights against closed forms --------------------------------------------

-- E / L at the origin (normal +y) through a diffuse floor kd = 0.8 seen head-on.
local function irradiance(lamp, samples)
  local sc = lancer.scene{camera = lancer.camera{from = {0, 0.5, 0}, at = {0, 0, 0},
                                                 up = {0, 0, 1}, fov = 0.5}}
  sc:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                      material = lancer.material{kd = 0.8}})
  lamp(sc)
  local img = sc:render{width = 1, height = 1, light_samples = samples}
  no_bad(img, "probe")
  return img:pixel(1, 1) * math.pi / 0.8
end

local glow = lancer.material{kd = 0, emission = 1}

T.test("area lights: a disc and a ring read pi R^2/(h^2 + R^2) less the hole's", function()
  local function disc_e(R, h) return math.pi * R * R / (h * h + R * R) end
  local e = irradiance(function(sc)
    sc:add(lancer.disc{center = {0, 1, 0}, normal = {0, -1, 0}, radius = 0.5, material = glow})
  end, 1024)
  T.near(e, disc_e(0.5, 1), 0.002 * disc_e(0.5, 1), "disc E/L")
  e = irradiance(function(sc)
    sc:add(lancer.disc{center = {0, 1, 0}, normal = {0, 1, 0}, radius = 0.5,
                       inner_radius = 0.3, material = glow})
  end, 1024)
  local want = disc_e(0.5, 1) - disc_e(0.3, 1)
  T.near(e, want, 0.003 * want, "ring E/L")
end)

T.test("area lights: an ellipsoid of equal radii, turned, is the sphere light (A2)", function()
  local e = irradiance(function(sc)
    sc:add(lancer.ellipsoid{center = {0, 0, 0}, radii = {0.25, 0.25, 0.25},
                            material = glow}:moved(lancer.translate(0, 2, 0) *
                                                   lancer.rotate({1, 1, 0}, 40)))
  end, 4096)
  T.near(e, 0.0490874, 0.003 * 0.0490874, "ellipsoid E/L")
end)

T.test("area lights: a capped coin (cylinder, cone) lights like its bottom disc", function()
  local want = math.pi * 0.16 / (1 + 0.16)
  local e = irradiance(function(sc)
    sc:add(lancer.cylinder{base = {0, 1, 0}, axis = {0, 1e-4, 0}, radius = 0.4,
                           material = glow})
  end, 2048)
  T.near(e, want, 0.005 * want, "cylinder coin E/L")
  e = irradiance(function(sc)
    sc:add(lancer.cone{base = {0, 1, 0}, axis = {0, 1e-4, 0}, base_radius = 0.4,
                       top_radius = 0.4, material = glow})
  end, 2048)
  T.near(e, want, 0.005 * want, "cone coin E/L")
end)

T.test("area lights: a torus light converges, and a thin one is its core ring", function()
  local function lamp(minor, y)
    return function(sc)
      sc:add(lancer.torus{center = {0, y, 0}, axis = {0, 1, 0}, major = 0.6, minor = minor,
                          material = glow})
    end
  end
  local rough, fine = irradiance(lamp(0.15, 1.5), 256), irradiance(lamp(0.15, 1.5), 4096)
  assert(fine > 0, "it lights")
  T.near(rough, fine, 0.02 * fine, "256 samples against 4096")
  -- A thin tube of radius a around a ring of radius R at height h above
  -- the point, seen from far against a: E/L = the ring's projected width
  -- over d^2, 2 pi R (2 a) h / d^3 with d^2 = R^2 + h^2, over 1 (convention
  -- E / pi of the small-source limit: pi L A cos / (pi d^2)).
  local a, R, h = 0.005, 0.6, 1.5
  local d = math.sqrt(R * R + h * h)
  local want = 2 * math.pi * R * 2 * a * h / (d * d * d)
  local e = irradiance(lamp(a, h), 4096)
  T.near(e, want, 0.01 * want, "thin torus E/L")
end)

-- ---- listing, removing, explain ---------------------------------------------------

T.test("the new kinds list, print, remove by value and name their hits", function()
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, -5}, at = {0, 0, 0}}}
  local cyl = lancer.cylinder{base = {0, -1, 0}, top = {0, 1, 0}, radius = 0.5}
  local sheared = lancer.torus{center = {0, 0, 0}, axis = {0, 1, 0}, major = 1, minor = 0.2}
                  :moved(lancer.scale(1, 2, 1))
  s:add(cyl, sheared, lancer.point_light{position = {0, 3, -3}})
  local objs = s:objects()
  T.eq(#objs, 3, "objects")
  T.eq(tostring(objs[1].object), tostring(cyl), "listed cylinder")
  T.has(tostring(objs[2].object), "lancer.torus{center = {0, 0, 0}, axis = {0, 1, 0}, " ..
        "major = 1, minor = 0.2} moved by lancer.transform{", "listed torus")
  T.eq(cyl.kind, "cylinder", "kind")
  T.eq(cyl.caps, true, "caps")
  T.eq(sheared.transform.kind, nil, "a transform")
  s:remove(sheared)
  local tree = s:explain{x = 16, y = 12, width = 32, height = 24}
  T.eq(tree.hit.shape, "cylinder 1", "explain's name")
  T.eq(#s:objects(), 2, "after removing the torus by value")
end)

-- ---- validation: every rule, naming the field ------------------------------------------

T.test("new constructors refuse bad fields, naming them", function()
  local E = function(f, ...) T.check_error(f, HERE, ...) end
  E(function() lancer.cylinder{base = {0, 0, 0}, radius = 1} end, "'cylinder'",
    "field 'axis'")
  E(function() lancer.cylinder{base = {0, 0, 0}, axis = {0, 1, 0}, top = {0, 1, 0},
                               radius = 1} end, "field 'top'", "either axis or top")
  E(function() lancer.cylinder{base = {0, 0, 0}, axis = {0, 0, 0}, radius = 1} end,
    "field 'axis'", "zero-length")
  E(function() lancer.cylinder{base = {0, 0, 0}, axis = {0, 1, 0}, radius = -1} end,
    "field 'radius'", "got -1")
  E(function() lancer.cylinder{base = {0, 0, 0}, axis = {0, 1, 0}, radius = 0 / 0} end,
    "field 'radius'")
  E(function() lancer.cylinder{base = {0, 0, 0}, axis = {0, 1, 0}, radius = 1, caps = 1} end,
    "field 'caps'", "boolean expected")
  E(function() lancer.cylinder{base = {0, 0, 0}, axis = {0, 1, 0}, radius = 1, cap = true} end,
    "unknown field 'cap'; did you mean 'caps'?")
  E(function() lancer.cone{base = {0, 0, 0}, top = {0, 1, 0}, base_radius = 0,
                           top_radius = 0} end, "field 'base_radius'", "got 0")
  E(function() lancer.cone{base = {0, 0, 0}, top = {0, 1, 0}, base_radius = -1,
                           top_radius = 1} end, "field 'base_radius'", ">= 0, got -1")
  E(function() lancer.cone{base = {0, 0, 0}, top = {0, 1, 0}, base_radius = 1} end,
    "field 'top_radius'")
  E(function() lancer.disc{center = {0, 0, 0}, normal = {0, 1, 0}, radius = 1,
                           inner_radius = 1} end, "field 'inner_radius'", "less than")
  E(function() lancer.disc{center = {0, 0, 0}, normal = {0, 0, 0}, radius = 1} end,
    "field 'normal'")
  E(function() lancer.torus{center = {0, 0, 0}, axis = {0, 1, 0}, major = 1, minor = 1} end,
    "field 'minor'", "less than major")
  E(function() lancer.torus{center = {0, 0, 0}, axis = {0, 1, 0}, major = 1, minor = "x"} end,
    "field 'minor'", "number expected, got string")
  E(function() lancer.torus{center = {0, 0, 0}, axis = {0, 1, 0}, mayor = 1, minor = 0.1} end,
    "unknown field 'mayor'; did you mean 'major'?")
  E(function() lancer.ellipsoid{center = {0, 0, 0}, radii = {1, 0, 1}} end,
    "field 'radii'", "got 0")
  E(function() lancer.ellipsoid{center = {0, 0, 0}, radii = {1, 1e31, 1}} end,
    "field 'radii'", "coordinate range")
  E(function() lancer.ellipsoid{center = {0, 0, 0}} end, "field 'radii'")
  E(function() lancer.cylinder{base = {0, 0, 0}, axis = {0, 1, 0}, radius = 1}:moved(
    lancer.scale(1e31)) end, "coordinate range")
end)

-- The constructors read a plain table (no metatable, plain vectors) in one
-- pass and fall back to the field-by-field reading for anything else; a
-- metatable on the table takes the fallback, so the two readings of the
-- same fields can be compared: the same shape, or the same error.
T.test("constructors: a plain table reads as the field-by-field reading does", function()
  local mat = lancer.material{color = {0.2, 0.4, 0.6}}
  local kinds = {
    sphere = {center = {1, 2, 3}, radius = 0.5},
    quad = {corner = {0, 0, 0}, u = {1, 0, 0}, v = {0, 2, 0}},
    plane = {point = {0, -1, 0}, normal = {0, 1, 0}},
    disc = {center = {0, 1, 0}, normal = {0, 0, 1}, radius = 2, inner_radius = 0.5},
    torus = {center = {0, 0, 0}, axis = {0, 1, 0}, major = 1, minor = 0.25},
    ellipsoid = {center = {0, 0, 0}, radii = {1, 2, 3}},
  }
  local bad = {"1", true, {1, 2}, {1, 2, 3, 4}, {1, "2", 3}, {0 / 0, 0, 0}, {1, 2, 1 / 0},
               0 / 0, 1 / 0, -1, 0, {}, setmetatable({1, 2, 3}, {}), mat}
  local function copy(t)
    local c = {}
    for k, v in pairs(t) do c[k] = v end
    return c
  end
  local function outcome(kind, fields)
    local ok, s = pcall(lancer[kind], fields)
    if not ok then return "error: " .. tostring(s) end
    return tostring(s) .. (rawequal(s.material, mat) and " +mat" or "")
  end
  local compared, errors = 0, 0
  local function same(kind, fields)
    local plain = outcome(kind, fields)
    local slow = outcome(kind, setmetatable(copy(fields), {}))
    T.eq(plain, slow, kind .. " read plain and read by field")
    compared = compared + 1
    if plain:find("^error") then errors = errors + 1 end
  end
  for kind, fields in pairs(kinds) do
    same(kind, fields)
    local m = copy(fields)
    m.material = mat
    same(kind, m)
    m.material = {}
    same(kind, m)
    for name in pairs(fields) do
      local without = copy(fields)
      without[name] = nil
      same(kind, without)
      for _, v in ipairs(bad) do
        local f = copy(fields)
        f[name] = v
        same(kind, f)
      end
    end
    local extra = copy(fields)
    extra.raduis = 1
    same(kind, extra)
    extra = copy(fields)
    extra[1] = 0
    same(kind, extra)
  end
  T.eq(compared, 285, "cases compared")
  assert(errors > 200 and errors < compared, "errors: " .. errors)
end)
