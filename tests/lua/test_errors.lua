-- test_errors.lua: every validation rule of the Lua API. Each error must be
-- raised at the caller's line (this file), name the function and the field,
-- and say what was wrong; a failing call leaves a scene as it was; no value,
-- however silly, crashes the process.
local T = require "harness"
local lancer = require "lancer"

local HERE = "test_errors.lua:"
local NAN, INF = 0 / 0, 1 / 0

-- A copy of `base` with t[k] = v (v == nil removes the field).
local function with(base, k, v)
  local t = {}
  for key, val in pairs(base) do t[key] = val end
  t[k] = v
  return t
end

-- Objects of each userdata type, to pass where another type is expected.
local MATERIAL = lancer.material{}
local SPHERE = lancer.sphere{center = {0, 0, 0}, radius = 1}
local LIGHT = lancer.point_light{position = {0, 5, 0}}
local CAMERA = lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}}

-- A tiny scene with a camera, and an image of it, for the method checks.
local fixture
local function fixtures()
  if not fixture then
    local s = lancer.scene{camera = CAMERA}
    s:add(SPHERE, LIGHT)
    local img = s:render{width = 16, height = 12, threads = 1}
    local png = os.tmpname()
    os.remove(png)              -- only its unique name is wanted
    fixture = {scene = s, img = img, png = png .. ".png"}
  end
  return fixture
end

-- ---- the argument tables, described once --------------------------------
-- Each function is called from a one-line wrapper (never a tail call, which
-- would lose the caller's line): the error must point at that line.
local CALL = {
  material    = function(t) lancer.material(t) end,
  sphere      = function(t) lancer.sphere(t) end,
  quad        = function(t) lancer.quad(t) end,
  box         = function(t) lancer.box(t) end,
  plane       = function(t) lancer.plane(t) end,
  point_light = function(t) lancer.point_light(t) end,
  camera      = function(t) lancer.camera(t) end,
  scene       = function(t) lancer.scene(t) end,
  render      = function(t) fixtures().scene:render(t) end,
  save        = function(t) fixtures().img:save(fixtures().png, t) end,
}

local function vec_fields(names, required)
  local out = {}
  for _, n in ipairs(names) do out[#out + 1] = {n, "vec", required} end
  return out
end
local function plus(list, ...)
  local out = {}
  for _, f in ipairs(list) do out[#out + 1] = f end
  for _, f in ipairs{...} do out[#out + 1] = f end
  return out
end

-- fn: the name the message must quote; argn: the argument number it reports;
-- fields: {name, kind, required}; other: fields of the other box form;
-- known: the list a no-near-match message gives; typo: {misspelling, hint};
-- nil_ok / empty_ok: whether nil / {} is a valid whole argument.
local SPECS = {
  {fn = "material", base = {}, empty_ok = true,
   fields = {{"color", "color"}, {"ka", "number"}, {"kd", "number"}, {"kr", "number"},
             {"ks", "number"}, {"alpha", "number"}, {"emission", "color"},
             {"absorb", "enum"}, {"kt", "number"}, {"ior", "number"}, {"fresnel", "bool"},
             {"absorption", "color"}, {"shadow", "enum"}},
   known = "color, ka, kd, kr, ks, alpha, emission, absorb, glossiness, cone_samples, kt, "
           .. "ior, fresnel, absorption, transmittance, shadow", typo = {"colour", "color"}},
  {fn = "sphere", base = {center = {0, 0, 0}, radius = 1},
   fields = {{"center", "vec", true}, {"radius", "number", true}, {"material", "material"}},
   known = "center, radius, material", typo = {"raduis", "radius"}},
  {fn = "quad", base = {corner = {0, 0, 0}, u = {1, 0, 0}, v = {0, 1, 0}},
   fields = plus(vec_fields({"corner", "u", "v"}, true), {"material", "material"}),
   known = "corner, u, v, material", typo = {"conrer", "corner"}},
  {fn = "box", label = "box{corner, u, v, w}",
   base = {corner = {0, 0, 0}, u = {1, 0, 0}, v = {0, 1, 0}, w = {0, 0, 1}},
   fields = plus(vec_fields({"corner", "u", "v", "w"}, true), {"material", "material"}),
   other = {"min", "max"},
   known = "corner, u, v, w, min, max, material", typo = {"cornr", "corner"}},
  {fn = "box", label = "box{min, max}", base = {min = {0, 0, 0}, max = {1, 1, 1}},
   fields = plus(vec_fields({"min", "max"}, true), {"material", "material"}),
   other = {"corner", "u", "v", "w"},
   known = "corner, u, v, w, min, max, material", typo = {"mx", "max"}},
  {fn = "plane", base = {point = {0, 0, 0}, normal = {0, 1, 0}},
   fields = plus(vec_fields({"point", "normal"}, true), {"material", "material"}),
   known = "point, normal, material", typo = {"normale", "normal"}},
  {fn = "point_light", base = {position = {0, 5, 0}},
   fields = {{"position", "vec", true}, {"color", "color"}, {"intensity", "number"},
             {"falloff", "enum"}},
   known = "position, color, intensity, falloff", typo = {"intensty", "intensity"}},
  {fn = "camera", base = {from = {0, 0, 5}, at = {0, 0, 0}},
   fields = {{"from", "vec", true}, {"at", "vec", true}, {"up", "vec"}, {"fov", "number"}},
   known = "from, at, up, fov", typo = {"fow", "fov"}},
  {fn = "scene", base = {}, nil_ok = true, empty_ok = true,
   fields = {{"camera", "camera"}, {"background", "color"}, {"ambient", "color"},
             {"max_depth", "integer"}},
   known = "camera, background, ambient, max_depth", typo = {"backgroud", "background"}},
  {fn = "render", base = {width = 2, height = 2}, nil_ok = true, empty_ok = true,
   fields = {{"width", "integer"}, {"height", "integer"}, {"samples", "integer"},
             {"seed", "seed"}, {"threads", "integer"}, {"cosine", "bool"}},
   known = "width, height, samples, seed, threads, cosine", typo = {"widht", "width"}},
  {fn = "save", argn = 2, base = {}, nil_ok = true, empty_ok = true,
   fields = {{"encoding", "enum"}},
   known = "encoding", typo = {"encodng", "encoding"}},
}

-- Calls CALL[spec.fn](arg), which must raise at the wrapper's own line with
-- "bad argument #n to 'fn'" and every further substring.
local function expect(spec, arg, ...)
  local call = CALL[spec.fn]
  local line = debug.getinfo(call, "S").linedefined
  return T.check_error(function() call(arg) end, HERE .. line .. ":",
    ("bad argument #%d to '%s'"):format(spec.argn or 1, spec.fn), ...)
end

-- Values of the wrong type for each kind of field, and what the message says.
local WRONG = {
  number = {{"1", "number expected, got string"}, {{}, "number expected, got table"},
            {true, "number expected, got boolean"}},
  seed = {{"1", "number expected, got string"}, {{}, "number expected, got table"}},
  integer = {{"3", "integer expected, got string"}, {{}, "integer expected, got table"},
             {1.5, "integer expected, got 1.5"}},
  vec = {{5, "vector {x, y, z} expected, got number"},
         {"x", "vector {x, y, z} expected, got string"},
         {{1, 2}, "3 components expected, got 2"},
         {{1, 2, 3, 4}, "3 components expected, got 4"},
         {{x = 1, y = 2, z = 3}, "3 components expected, got 0"},
         {{1, "2", 3}, "component 2: number expected, got string"}},
  color = {{"red", "colour {r, g, b} or number expected, got string"},
           {true, "colour {r, g, b} or number expected, got boolean"},
           {{1, 1}, "3 components expected, got 2"},
           {{0, 0, 0, 0}, "3 components expected, got 4"},
           {{1, 1, "x"}, "component 3: number expected, got string"}},
  enum = {{1, "string expected, got number"}, {true, "string expected, got boolean"}},
  bool = {{1, "boolean expected, got number"}, {"true", "boolean expected, got string"}},
  material = {{5, "lancer.Material expected, got number"},
              {{}, "lancer.Material expected, got table"},
              {LIGHT, "lancer.Material expected, got lancer.Light"},
              {CAMERA, "lancer.Material expected, got lancer.Camera"},
              {SPHERE, "lancer.Material expected, got lancer.Shape"}},
  camera = {{5, "lancer.Camera expected, got number"},
            {LIGHT, "lancer.Camera expected, got lancer.Light"},
            {MATERIAL, "lancer.Camera expected, got lancer.Material"}},
}

-- NaN and infinities: {value, substrings of the message}.
local function nonfinite(kind)
  local out = {}
  if kind == "number" or kind == "integer" or kind == "seed" then
    out = {{NAN, {"NaN"}}, {INF, {"got inf"}}, {-INF, {"got -inf"}},
           {math.huge, {"got inf"}}}
  elseif kind == "vec" or kind == "color" then
    if kind == "color" then     -- one number for grey
      out = {{NAN, {"must be finite", "nan"}}, {INF, {"must be finite, got inf"}},
             {-INF, {"must be finite, got -inf"}}, {math.huge, {"must be finite, got inf"}}}
    end
    for i = 1, 3 do
      for _, bad in ipairs{{NAN, "NaN in component " .. i},
                           {INF, "infinite component " .. i},
                           {-INF, "infinite component " .. i},
                           {math.huge, "infinite component " .. i}} do
        local v = {0.5, 0.5, 0.5}
        v[i] = bad[1]
        out[#out + 1] = {v, {bad[2]}}
      end
    end
  end
  return out
end

-- ---- generic rules, for every function that takes named fields ----------
for _, spec in ipairs(SPECS) do
  local name = spec.label or spec.fn

  if spec.label ~= "box{min, max}" then
    T.test(name .. ": the argument must be a table", function()
      local bad = {{5, "got number"}, {"x", "got string"}, {true, "got boolean"}}
      if not spec.nil_ok then bad[#bad + 1] = {nil, "got nil"} end
      for _, b in ipairs(bad) do
        expect(spec, b[1], "table of named fields expected, " .. b[2])
      end
    end)

    T.test(name .. ": positional keys are rejected", function()
      expect(spec, with(spec.base, 1, 5), "unexpected key [1]", "fields are named")
    end)

    T.test(name .. ": a misspelt field gets a did-you-mean hint", function()
      expect(spec, with(spec.base, spec.typo[1], 1),
        ("unknown field '%s'; did you mean '%s'?"):format(spec.typo[1], spec.typo[2]))
    end)

    T.test(name .. ": an unknown field with no near match lists the known fields", function()
      expect(spec, with(spec.base, "xyzzy", 1),
        "unknown field 'xyzzy'; known fields are " .. spec.known)
    end)
  end

  for _, f in ipairs(spec.fields) do
    local field, kind, required = f[1], f[2], f[3]
    if required then
      T.test(("%s: field '%s' is required"):format(name, field), function()
        expect(spec, with(spec.base, field, nil), "field '" .. field .. "'", "got no value")
      end)
    end

    T.test(("%s: field '%s' of the wrong type"):format(name, field), function()
      for _, w in ipairs(WRONG[kind]) do
        expect(spec, with(spec.base, field, w[1]), "field '" .. field .. "': " .. w[2])
      end
    end)

    local cases = nonfinite(kind)
    if #cases > 0 then
      T.test(("%s: NaN and infinities in field '%s'"):format(name, field), function()
        for _, c in ipairs(cases) do
          expect(spec, with(spec.base, field, c[1]), "field '" .. field .. "'",
            table.unpack(c[2]))
        end
      end)
    end
  end
end

-- ---- no argument at all ---------------------------------------------------
T.test("constructors called with no argument say 'no value'", function()
  T.check_error(function() lancer.material() end, HERE, "'material'", "got no value")
  T.check_error(function() lancer.sphere() end, HERE, "'sphere'", "got no value")
  T.check_error(function() lancer.quad() end, HERE, "'quad'", "got no value")
  T.check_error(function() lancer.box() end, HERE, "'box'", "got no value")
  T.check_error(function() lancer.plane() end, HERE, "'plane'", "got no value")
  T.check_error(function() lancer.point_light() end, HERE, "'point_light'", "got no value")
  T.check_error(function() lancer.camera() end, HERE, "'camera'", "got no value")
end)

T.test("positional vector given where the table of fields belongs", function()
  T.check_error(function() lancer.sphere{1, 2, 3} end, HERE, "'sphere'",
                "unexpected key [1]")
end)

-- ---- materials ------------------------------------------------------------
T.test("material: colour components must be in [0, 1]", function()
  T.check_error(function() lancer.material{color = 2} end, HERE, "'material'",
                "field 'color'", "component 1 must be in [0, 1], got 2")
  T.check_error(function() lancer.material{color = {1, 1.5, 1}} end, HERE, "'material'",
                "field 'color'", "component 2 must be in [0, 1], got 1.5")
  T.check_error(function() lancer.material{color = {1, 1, 1.0001}} end, HERE,
                "'material'", "field 'color'", "component 3 must be in [0, 1]")
end)

T.test("material: negative colour components", function()
  T.check_error(function() lancer.material{color = {0.5, -0.5, 0.5}} end, HERE,
                "'material'", "field 'color'", "component 2", "got -0.5")
  T.check_error(function() lancer.material{color = -1} end, HERE, "'material'",
                "field 'color'", "got -1")
end)

T.test("material: negative emission components", function()
  T.check_error(function() lancer.material{emission = {0, 0, -1}} end, HERE,
                "'material'", "field 'emission'", "component 3", ">= 0", "got -1")
  T.check_error(function() lancer.material{emission = -2} end, HERE, "'material'",
                "field 'emission'", ">= 0", "got -2")
end)

T.test("material: coefficients must be >= 0", function()
  T.check_error(function() lancer.material{ka = -1} end, HERE, "'material'",
                "field 'ka'", "must be >= 0, got -1")
  T.check_error(function() lancer.material{kd = -0.5} end, HERE, "'material'",
                "field 'kd'", "must be >= 0, got -0.5")
  T.check_error(function() lancer.material{kr = -1} end, HERE, "'material'",
                "field 'kr'", "must be >= 0, got -1")
  T.check_error(function() lancer.material{ks = -1} end, HERE, "'material'",
                "field 'ks'", "must be >= 0, got -1")
  T.check_error(function() lancer.material{alpha = -32} end, HERE, "'material'",
                "field 'alpha'", "must be >= 0, got -32")
end)

T.test("material: absorb is one of 'all', 'diffuse'", function()
  T.check_error(function() lancer.material{absorb = "glas"} end, HERE, "'material'",
                "field 'absorb'", "expected one of 'all', 'diffuse', got 'glas'")
  T.check_error(function() lancer.material{absorb = "ALL"} end, HERE, "'material'",
                "field 'absorb'", "expected one of 'all', 'diffuse', got 'ALL'")
end)

T.test("material: kt >= 0, ior in [1, 100]", function()
  T.check_error(function() lancer.material{kt = -1} end, HERE, "'material'",
                "field 'kt'", "must be >= 0, got -1")
  for _, bad in ipairs{0.5, 0, -1.5, 100.5, 1e300} do
    T.check_error(function() lancer.material{kt = 1, ior = bad} end, HERE, "'material'",
                  "field 'ior'", "must be in [1, 100], got " .. ("%g"):format(bad))
  end
end)

T.test("material: absorption components in [0, 1e30] per unit length", function()
  T.check_error(function() lancer.material{absorption = {0.1, -0.1, 0}} end, HERE,
                "'material'", "field 'absorption'", "component 2 must be in [0, 1e+30]",
                "got -0.1")
  T.check_error(function() lancer.material{absorption = 1e31} end, HERE, "'material'",
                "field 'absorption'", "component 1", "got 1e+31")
end)

T.test("material: transmittance = {colour, distance}, or absorption, not both", function()
  local function bad(t, ...)
    T.check_error(function() lancer.material{transmittance = t} end, HERE, "'material'",
                  "field 'transmittance'", ...)
  end
  bad(0.5, "{colour, distance} expected, got number")
  bad({0.5}, "{colour, distance} expected, got 1 entries")
  bad({0.5, 1, 2}, "got 3 entries")
  bad({{1, 1}, 2}, "colour: 3 components expected, got 2")
  bad({"red", 2}, "colour: colour {r, g, b} or number expected, got string")
  bad({{1, 0 / 0, 1}, 2}, "colour: NaN in component 2")
  bad({0, 1}, "colour component 1 must be in (0, 1], got 0")
  bad({{0.5, 1.5, 0.5}, 1}, "colour component 2 must be in (0, 1], got 1.5")
  bad({0.5, 0}, "distance must be in (0, 1e+30], got 0")
  bad({0.5, -2}, "got -2")
  bad({0.5, 0 / 0}, "distance must be in (0, 1e+30], got ", "nan")
  bad({0.5, 1 / 0}, "got inf")
  bad({0.5, "far"}, "distance: number expected, got string")
  T.check_error(function() lancer.material{absorption = 1, transmittance = {0.5, 1}} end,
                HERE, "'material'", "field 'transmittance'", "'absorption' is given too")
end)

T.test("material: shadow is one of 'filtered', 'opaque'; misspelt fields get a hint", function()
  T.check_error(function() lancer.material{shadow = "opaq"} end, HERE, "'material'",
                "field 'shadow'", "expected one of 'filtered', 'opaque', got 'opaq'")
  for typo, hint in pairs{iro = "ior", absorbtion = "absorption", frenel = "fresnel",
                          transmitance = "transmittance", tk = "kt"} do
    T.check_error(function() lancer.material{[typo] = 1} end, HERE, "'material'",
                  ("unknown field '%s'; did you mean '%s'?"):format(typo, hint))
  end
end)

-- A finite double beyond float range cannot be stored in a colour; the message
-- must say so, not claim that a positive value is below zero.
T.test("colour components beyond float range are rejected with a true reason", function()
  local function no_false_claim(msg)
    assert(not msg:find(">= 0", 1, true),
           "message says the positive value 1e+39 breaks '>= 0': " .. msg)
  end
  no_false_claim(T.check_error(function() lancer.material{emission = 1e39} end, HERE,
                 "'material'", "field 'emission'", "1e+39"))
  no_false_claim(T.check_error(function() lancer.material{color = {1, 1e39, 1}} end,
                 HERE, "'material'", "field 'color'", "1e+39"))
  no_false_claim(T.check_error(function() lancer.point_light{position = {0, 1, 0},
                 color = 1e39} end, HERE, "'point_light'", "field 'color'", "1e+39"))
  no_false_claim(T.check_error(function() lancer.scene{background = {0, 0, 1e39}} end,
                 HERE, "'scene'", "field 'background'", "1e+39"))
end)

-- ---- shapes -----------------------------------------------------------------
T.test("sphere: radius must be > 0", function()
  T.check_error(function() lancer.sphere{center = {0, 0, 0}, radius = 0} end, HERE,
                "'sphere'", "field 'radius'", "must be > 0, got 0")
  T.check_error(function() lancer.sphere{center = {0, 0, 0}, radius = -2} end, HERE,
                "'sphere'", "field 'radius'", "must be > 0, got -2")
end)

T.test("quad: edges must not be zero-length", function()
  T.check_error(function() lancer.quad{corner = {0, 0, 0}, u = {0, 0, 0}, v = {0, 1, 0}}
                end, HERE, "'quad'", "field 'u'", "zero-length")
  T.check_error(function() lancer.quad{corner = {0, 0, 0}, u = {1, 0, 0}, v = {0, 0, 0}}
                end, HERE, "'quad'", "field 'v'", "zero-length")
end)

T.test("shapes outside the coordinate range are refused, naming the field", function()
  T.check_error(function() lancer.sphere{center = {0, 0, 0}, radius = 1e39} end, HERE,
                "'sphere'", "field 'radius'", "coordinate range", "1e+39")
  T.check_error(function() lancer.sphere{center = {0, 0, 0}, radius = 1e-31} end, HERE,
                "'sphere'", "field 'radius'", "coordinate range", "1e-31")
  T.check_error(function() lancer.sphere{center = {2e30, 0, 0}, radius = 1} end, HERE,
                "'sphere'", "field 'center'", "within +-1e+30")
  T.check_error(function() lancer.quad{corner = {0, 0, 0}, u = {1e-31, 0, 0},
                v = {0, 1, 0}} end, HERE, "'quad'", "field 'u'", "coordinate range")
  T.check_error(function() lancer.box{corner = {0, 0, 0}, u = {1, 0, 0}, v = {0, 1, 0},
                w = {0, 0, 1e31}} end, HERE, "'box'", "field 'w'", "coordinate range")
  T.check_error(function() lancer.camera{from = {0, 0, -4e152}, at = {0, 0, 0}} end, HERE,
                "'camera'", "field 'from'", "coordinate range")
  T.check_error(function() lancer.point_light{position = {0, 1e31, 0}} end, HERE,
                "'point_light'", "field 'position'", "coordinate range")
  T.check_error(function() lancer.triangle{a = {0, 0, 0}, b = {1, 0, 0}, c = {0, 1e31, 0}}
                end, HERE, "'triangle'", "field 'c'", "coordinate range")
  -- the edges of the range are in it
  lancer.sphere{center = {1e30, -1e30, 0}, radius = 1e-30}
  lancer.sphere{center = {0, 0, 0}, radius = 1e30}
end)

T.test("quad: an edge too short to have a direction is rejected", function()
  T.check_error(function() lancer.quad{corner = {0, 0, 0}, u = {1e-300, 0, 0},
                v = {0, 1, 0}} end, HERE, "'quad'", "field 'u'", "out of range", "1e-300")
end)

T.test("quad: u and v must not be parallel, at any scale", function()
  T.check_error(function() lancer.quad{corner = {0, 0, 0}, u = {1, 2, 3}, v = {2, 4, 6}}
                end, HERE, "'quad'", "field 'v'", "'u' and 'v' must not be parallel")
  T.check_error(function() lancer.quad{corner = {0, 0, 0}, u = {1, 0, 0}, v = {-2, 0, 0}}
                end, HERE, "'quad'", "field 'v'", "must not be parallel")
  T.check_error(function() lancer.quad{corner = {0, 0, 0}, u = {1e-25, 0, 0},
                v = {1, 0, 0}} end, HERE, "'quad'", "field 'v'", "must not be parallel")
  T.check_error(function() lancer.quad{corner = {0, 0, 0}, u = {1e25, 1e25, 0},
                v = {1, 1, 0}} end, HERE, "'quad'", "field 'v'", "must not be parallel")
  -- the test is on directions: tiny and huge perpendicular edges are fine
  lancer.quad{corner = {0, 0, 0}, u = {1e-25, 0, 0}, v = {0, 1e-25, 0}}
  lancer.quad{corner = {0, 0, 0}, u = {1e25, 0, 0}, v = {0, 1, 0}}
end)

T.test("box: edges must not be zero-length", function()
  T.check_error(function() lancer.box{corner = {0, 0, 0}, u = {0, 0, 0}, v = {0, 1, 0},
                w = {0, 0, 1}} end, HERE, "'box'", "field 'u'", "zero-length")
  T.check_error(function() lancer.box{corner = {0, 0, 0}, u = {1, 0, 0}, v = {0, 0, 0},
                w = {0, 0, 1}} end, HERE, "'box'", "field 'v'", "zero-length")
  T.check_error(function() lancer.box{corner = {0, 0, 0}, u = {1, 0, 0}, v = {0, 1, 0},
                w = {0, 0, 0}} end, HERE, "'box'", "field 'w'", "zero-length")
end)

T.test("box: no two edges parallel", function()
  T.check_error(function() lancer.box{corner = {0, 0, 0}, u = {1, 0, 0}, v = {-3, 0, 0},
                w = {0, 0, 1}} end, HERE, "'box'", "field 'v'",
                "'u' and 'v' must not be parallel")
  T.check_error(function() lancer.box{corner = {0, 0, 0}, u = {1, 0, 0}, v = {0, 1, 0},
                w = {0, 2, 0}} end, HERE, "'box'", "field 'w'",
                "'v' and 'w' must not be parallel")
  T.check_error(function() lancer.box{corner = {0, 0, 0}, u = {1, 0, 0}, v = {0, 1, 0},
                w = {5, 0, 0}} end, HERE, "'box'", "field 'w'",
                "'u' and 'w' must not be parallel")
end)

T.test("box: u, v and w must not be coplanar", function()
  T.check_error(function() lancer.box{corner = {0, 0, 0}, u = {1, 0, 0}, v = {0, 1, 0},
                w = {1, 1, 0}} end, HERE, "'box'", "field 'w'",
                "'u', 'v' and 'w' must not be coplanar")
  T.check_error(function() lancer.box{corner = {0, 0, 0}, u = {1, 0, 1}, v = {0, 1, 1},
                w = {1, 1, 2}} end, HERE, "'box'", "field 'w'", "coplanar")
end)

T.test("box: max must exceed min on every axis", function()
  for axis = 1, 3 do
    for _, hi in ipairs{0, -1} do
      local max = {1, 1, 1}
      max[axis] = hi
      T.check_error(function() lancer.box{min = {0, 0, 0}, max = max} end,
        HERE, "'box'", "field 'max'",
        ("component %d must be > min's, got %g <= 0"):format(axis, hi))
    end
  end
end)

T.test("box: the two forms cannot be mixed", function()
  T.check_error(function() lancer.box{min = {0, 0, 0}, max = {1, 1, 1},
                corner = {0, 0, 0}} end, HERE, "'box'", "field 'corner'",
                "give either min and max, or corner and u, v, w, not both")
  T.check_error(function() lancer.box{max = {1, 1, 1}, w = {0, 0, 1}} end, HERE, "'box'",
                "field 'w'", "not both")
end)

T.test("box: min and max come together", function()
  T.check_error(function() lancer.box{min = {0, 0, 0}} end, HERE, "'box'",
                "field 'max'", "got no value")
  T.check_error(function() lancer.box{max = {1, 1, 1}} end, HERE, "'box'",
                "field 'min'", "got no value")
end)

T.test("plane: normal must not be zero-length", function()
  T.check_error(function() lancer.plane{point = {0, 0, 0}, normal = {0, 0, 0}} end, HERE,
                "'plane'", "field 'normal'", "zero-length")
end)

T.test("shapes: material must be a lancer.Material", function()
  T.check_error(function() lancer.sphere{center = {0, 0, 0}, radius = 1,
                material = LIGHT} end, HERE, "'sphere'", "field 'material'",
                "lancer.Material expected, got lancer.Light")
  T.check_error(function() lancer.quad{corner = {0, 0, 0}, u = {1, 0, 0}, v = {0, 1, 0},
                material = CAMERA} end, HERE, "'quad'", "field 'material'",
                "lancer.Material expected, got lancer.Camera")
  T.check_error(function() lancer.box{min = {0, 0, 0}, max = {1, 1, 1},
                material = SPHERE} end, HERE, "'box'", "field 'material'",
                "lancer.Material expected, got lancer.Shape")
  T.check_error(function() lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                material = {color = 1}} end, HERE, "'plane'", "field 'material'",
                "lancer.Material expected, got table")
end)

-- ---- lights -------------------------------------------------------------------
T.test("point_light: colour components must be >= 0", function()
  T.check_error(function() lancer.point_light{position = {0, 1, 0}, color = {1, -1, 1}}
                end, HERE, "'point_light'", "field 'color'", "component 2", "got -1")
end)

T.test("point_light: intensity must be >= 0", function()
  T.check_error(function() lancer.point_light{position = {0, 1, 0}, intensity = -5} end,
                HERE, "'point_light'", "field 'intensity'", "must be >= 0, got -5")
end)

T.test("point_light: falloff is one of 'inverse_square', 'none'", function()
  T.check_error(function() lancer.point_light{position = {0, 1, 0}, falloff = "linear"}
                end, HERE, "'point_light'", "field 'falloff'",
                "expected one of 'inverse_square', 'none', got 'linear'")
end)

-- ---- cameras -----------------------------------------------------------------
T.test("camera: up must not be zero-length", function()
  T.check_error(function() lancer.camera{from = {0, 0, 5}, at = {0, 0, 0},
                up = {0, 0, 0}} end, HERE, "'camera'", "field 'up'", "zero-length")
end)

T.test("camera: at must differ from from", function()
  T.check_error(function() lancer.camera{from = {1, 2, 3}, at = {1, 2, 3}} end, HERE,
                "'camera'", "field 'at'", "must differ from 'from'")
end)

T.test("camera: up must not be parallel to the view direction", function()
  T.check_error(function() lancer.camera{from = {0, 0, 0}, at = {0, 3, 0}} end, HERE,
                "'camera'", "field 'up'", "must not be parallel")
  T.check_error(function() lancer.camera{from = {0, 0, 0}, at = {0, -3, 0}} end, HERE,
                "'camera'", "field 'up'", "must not be parallel")
  T.check_error(function() lancer.camera{from = {0, 0, 0}, at = {1, 1, 1},
                up = {2, 2, 2}} end, HERE, "'camera'", "field 'up'", "must not be parallel")
end)

T.test("camera: fov must be in (0, 180) degrees", function()
  T.check_error(function() lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}, fov = 0} end,
                HERE, "'camera'", "field 'fov'", "(0, 180)", "got 0")
  T.check_error(function() lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}, fov = 180}
                end, HERE, "'camera'", "field 'fov'", "(0, 180)", "got 180")
  T.check_error(function() lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}, fov = -5} end,
                HERE, "'camera'", "field 'fov'", "(0, 180)", "got -5")
  T.check_error(function() lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}, fov = 200}
                end, HERE, "'camera'", "field 'fov'", "(0, 180)", "got 200")
end)

-- ---- scenes --------------------------------------------------------------------
T.test("scene: max_depth must be >= 0", function()
  T.check_error(function() lancer.scene{max_depth = -1} end, HERE, "'scene'",
                "field 'max_depth'", "must be in [0, 1000000], got -1")
end)

T.test("scene: max_depth must be an integer", function()
  T.check_error(function() lancer.scene{max_depth = 1.5} end, HERE, "'scene'",
                "field 'max_depth'", "integer expected, got 1.5")
end)

T.test("scene: background and ambient components must be >= 0", function()
  T.check_error(function() lancer.scene{background = {0, -0.1, 0}} end, HERE, "'scene'",
                "field 'background'", "component 2", "got -0.1")
  T.check_error(function() lancer.scene{ambient = -1} end, HERE, "'scene'",
                "field 'ambient'", "got -1")
end)

T.test("scene: camera must be a lancer.Camera", function()
  T.check_error(function() lancer.scene{camera = LIGHT} end, HERE, "'scene'",
                "field 'camera'", "lancer.Camera expected, got lancer.Light")
end)

T.test("scene.max_depth = -1 is rejected", function()
  local s = lancer.scene{}
  T.check_error(function() s.max_depth = -1 end, HERE, "scene.max_depth",
                "must be in [0, 1000000], got -1")
  T.check_error(function() s.max_depth = 1 << 40 end, HERE, "scene.max_depth",
                "integer in [0, 1000000] expected, got 1099511627776")
  T.check_error(function() s.max_depth = 1.5 end, HERE, "scene.max_depth",
                "integer in [0, 1000000] expected, got 1.5")
  T.check_error(function() s.max_depth = "3" end, HERE, "scene.max_depth",
                "integer in [0, 1000000] expected, got 3")
end)

T.test("scene.max_depth = NaN or infinity is rejected", function()
  local s = lancer.scene{}
  T.check_error(function() s.max_depth = NAN end, HERE, "scene.max_depth", "nan")
  T.check_error(function() s.max_depth = INF end, HERE, "scene.max_depth", "got inf")
  T.check_error(function() s.max_depth = -INF end, HERE, "scene.max_depth", "got -inf")
  T.check_error(function() s.max_depth = math.huge end, HERE, "scene.max_depth", "inf")
end)

-- lancer.scene{max_depth = 2.0} is accepted (2.0 is an integer in Lua 5.4's
-- sense, as luaL_checkinteger has it); the setter must agree.
T.test("scene.max_depth accepts the integral float lancer.scene accepts", function()
  local s = lancer.scene{max_depth = 2.0}
  T.eq(s.max_depth, 2, "lancer.scene{max_depth = 2.0}")
  local ok, err = pcall(function() s.max_depth = 4.0 end)
  assert(ok, "scene.max_depth = 4.0 rejected: " .. tostring(err))
  T.eq(s.max_depth, 4, "scene.max_depth after = 4.0")
end)

-- The setter refuses more than 1000000; the constructor must not accept what
-- the setter refuses.
T.test("scene: max_depth has the same upper bound in lancer.scene and the setter", function()
  local s = lancer.scene{}
  T.check_error(function() s.max_depth = 1000001 end, HERE, "scene.max_depth",
                "got 1000001")
  T.check_error(function() lancer.scene{max_depth = 1000001} end, HERE, "'scene'",
                "field 'max_depth'", "1000001")
end)

T.test("scene.background and scene.ambient reject bad colours", function()
  local s = lancer.scene{}
  T.check_error(function() s.background = -1 end, HERE, "scene.background",
                ">= 0", "got -1")
  T.check_error(function() s.background = {1, NAN, 1} end, HERE, "scene.background",
                "NaN in component 2")
  T.check_error(function() s.background = "black" end, HERE, "scene.background",
                "got string")
  T.check_error(function() s.ambient = {0, 0, -0.5} end, HERE, "scene.ambient",
                "component 3", "got -0.5")
  T.check_error(function() s.ambient = {0, 0, INF} end, HERE, "scene.ambient",
                "infinite component 3")
  T.check_error(function() s.ambient = NAN end, HERE, "scene.ambient",
                "must be finite", "nan")
  T.check_error(function() s.ambient = -INF end, HERE, "scene.ambient",
                "must be finite, got -inf")
  T.check_error(function() s.ambient = {1, 1} end, HERE, "scene.ambient",
                "3 components expected, got 2")
end)

T.test("scene.camera = 5 names lancer.Camera", function()
  local s = lancer.scene{}
  T.check_error(function() s.camera = 5 end, HERE, "scene.camera",
                "lancer.Camera expected, got number")
  T.check_error(function() s.camera = MATERIAL end, HERE, "scene.camera",
                "lancer.Camera expected, got lancer.Material")
  T.check_error(function() s.camera = nil end, HERE, "scene.camera",
                "lancer.Camera expected, got nil")
end)

T.test("scene.unknown = 1 is an error that lists the settable fields", function()
  local s = lancer.scene{}
  T.check_error(function() s.unknown = 1 end, HERE, "scene.unknown", "unknown field",
                "camera, background, ambient, max_depth")
  T.check_error(function() s.add = 1 end, HERE, "scene.add", "unknown field")
end)

-- ---- scene:add -------------------------------------------------------------------
T.test("scene:add() needs something to add", function()
  local s = lancer.scene{}
  T.check_error(function() s:add() end, HERE, "bad argument #1 to 'add'",
                "shape, mesh, light, group, CSG object or array of them expected, "
                .. "got no value")
end)

T.test("scene:add rejects what is neither shape, light nor array", function()
  local s = lancer.scene{}
  T.check_error(function() s:add(5) end, HERE, "bad argument #1 to 'add'",
                "shape, mesh, light, group, CSG object or array of them expected, "
                .. "got number")
  T.check_error(function() s:add(MATERIAL) end, HERE, "bad argument #1 to 'add'",
                "got lancer.Material")
  T.check_error(function() s:add(CAMERA) end, HERE, "bad argument #1 to 'add'",
                "got lancer.Camera")
  T.check_error(function() s:add(SPHERE, "x") end, HERE, "bad argument #2 to 'add'",
                "got string")
end)

T.test("scene:add of an array with a bad element", function()
  local s = lancer.scene{}
  T.check_error(function() s:add({SPHERE, 5}) end, HERE, "bad argument #1 to 'add'",
                "shape, mesh, light, group, CSG object or array of them expected, "
                .. "got number")
  T.check_error(function() s:add({LIGHT, {SPHERE, MATERIAL}}) end, HERE,
                "bad argument #1 to 'add'", "got lancer.Material")
end)

T.test("scene:add called on something that is not a scene", function()
  local s = lancer.scene{}
  T.check_error(function() s.add(5, SPHERE) end, HERE, "'add'",
                "lancer.Scene expected, got number")
end)

-- ---- scene:render --------------------------------------------------------------
T.test("render without a camera says so", function()
  local s = lancer.scene{}
  s:add(SPHERE)
  T.check_error(function() s:render{width = 4, height = 4} end, HERE, "render:",
                "camera")
end)

T.test("render: width must be in [1, 1048576]", function()
  local s = fixtures().scene
  for _, w in ipairs{0, -1, 1048577} do
    T.check_error(function() s:render{width = w, height = 4} end, HERE,
                  "bad argument #1 to 'render'", "field 'width'", "[1, 1048576]", "got " .. w)
  end
end)

T.test("render: height must be in [1, 1048576]", function()
  local s = fixtures().scene
  for _, h in ipairs{0, -1, 1048577} do
    T.check_error(function() s:render{width = 4, height = h} end, HERE,
                  "bad argument #1 to 'render'", "field 'height'", "[1, 1048576]", "got " .. h)
  end
end)

T.test("render: a 70000 x 1 panorama strip renders and saves", function()
  local s = fixtures().scene
  local img = s:render{width = 70000, height = 1}
  T.eq(img.width, 70000, "width")
  local path = os.tmpname() .. ".png"
  img:save(path)
  local back = lancer.load_png(path)
  os.remove(path)
  T.eq(back.width, 70000, "width read back")
  T.eq(back.height, 1, "height read back")
end)

T.test("render: width times height is bounded", function()
  local s = fixtures().scene
  T.check_error(function() s:render{width = 65536, height = 65536} end, HERE, "'render'",
                "field 'width'", "65536x65536", "268435456")
end)

T.test("render: samples must be in [1, 1048576]", function()
  local s = fixtures().scene
  T.check_error(function() s:render{width = 2, height = 2, samples = 0} end, HERE,
                "'render'", "field 'samples'", "got 0")
  T.check_error(function() s:render{width = 2, height = 2, samples = -3} end, HERE,
                "'render'", "field 'samples'", "got -3")
  T.check_error(function() s:render{width = 2, height = 2, samples = 1048577} end, HERE,
                "'render'", "field 'samples'", "got 1048577")
end)

T.test("render: threads must be in [0, 256]", function()
  local s = fixtures().scene
  T.check_error(function() s:render{width = 2, height = 2, threads = -1} end, HERE,
                "'render'", "field 'threads'", "[0, 256]", "got -1")
  T.check_error(function() s:render{width = 2, height = 2, threads = 257} end, HERE,
                "'render'", "field 'threads'", "[0, 256]", "got 257")
end)

T.test("render: seed must be a non-negative integer", function()
  local s = fixtures().scene
  T.check_error(function() s:render{width = 2, height = 2, seed = -1} end, HERE,
                "'render'", "field 'seed'", "non-negative integer expected, got -1")
  T.check_error(function() s:render{width = 2, height = 2, seed = 1.5} end, HERE,
                "'render'", "field 'seed'", "non-negative integer expected, got 1.5")
end)

-- The range is the core's rule (lc_render_options_check); its message names it.
T.test("render: cutoff must be in [0, 1]", function()
  local s = fixtures().scene
  T.check_error(function() s:render{width = 2, height = 2, cutoff = 2} end, HERE,
                "bad argument #1 to 'render'", "field 'cutoff'", "must be in [0, 1], got 2")
  T.check_error(function() s:render{width = 2, height = 2, cutoff = -0.5} end, HERE,
                "'render'", "field 'cutoff'", "got -0.5")
end)

-- ---- images ----------------------------------------------------------------------
T.test("img:pixel x out of range names x and the range", function()
  local img = fixtures().img
  T.check_error(function() img:pixel(0, 1) end, HERE, "bad argument #1 to 'pixel'",
                "x must be in [1, 16], got 0")
  T.check_error(function() img:pixel(17, 1) end, HERE, "bad argument #1 to 'pixel'",
                "x must be in [1, 16], got 17")
end)

T.test("img:pixel y out of range names y and the range", function()
  local img = fixtures().img
  T.check_error(function() img:pixel(1, 0) end, HERE, "bad argument #2 to 'pixel'",
                "y must be in [1, 12], got 0")
  T.check_error(function() img:pixel(1, 13) end, HERE, "bad argument #2 to 'pixel'",
                "y must be in [1, 12], got 13")
end)

T.test("img:pixel coordinates must be integers", function()
  local img = fixtures().img
  T.check_error(function() img:pixel("a", 1) end, HERE, "bad argument #1 to 'pixel'",
                "number expected, got string")
  T.check_error(function() img:pixel(1.5, 1) end, HERE, "bad argument #1 to 'pixel'",
                "no integer representation")
  T.check_error(function() img:pixel(1, NAN) end, HERE, "bad argument #2 to 'pixel'",
                "no integer representation")
  T.check_error(function() img:pixel(1) end, HERE, "bad argument #2 to 'pixel'",
                "got no value")
end)

T.test("img:save to a missing directory raises 'cannot write' with the path", function()
  local img = fixtures().img
  local path = "/nonexistent-lancer-test-dir/out.png"
  T.check_error(function() img:save(path) end, HERE, "cannot write",
                "'" .. path .. "'", "No such file or directory", "'save'")
end)

T.test("img:save with an empty path", function()
  local img = fixtures().img
  T.check_error(function() img:save("") end, HERE, "empty", "'save'")
end)

T.test("img:save refuses an extension it cannot write", function()
  local img = fixtures().img
  -- (.exr is a format lancer writes since issue 16.)
  for _, name in ipairs{"out.jpg", "out.tiff", "out.PNG.bak", "dir.png/out"} do
    T.check_error(function() img:save(name) end, HERE, "bad argument #1 to 'save'",
                  "cannot write '" .. name .. "'", "lancer writes .png")
  end
  T.check_error(function() img:save("out.jpg") end, HERE, "unknown extension '.jpg'")
end)

T.test("img:save path of the wrong type", function()
  local img = fixtures().img
  T.check_error(function() img:save() end, HERE, "bad argument #1 to 'save'",
                "string expected, got no value")
  T.check_error(function() img:save(true) end, HERE, "bad argument #1 to 'save'",
                "string expected, got boolean")
  T.check_error(function() img:save({}) end, HERE, "bad argument #1 to 'save'",
                "string expected, got table")
end)

-- luaL_checkstring converts numbers: img:save(123) would write a file "123".
T.test("img:save(123) is a type error, not a file named 123", function()
  local img = fixtures().img
  assert(not io.open("123", "rb"), "a file named 123 is in the way; not running")
  local ok, err = pcall(T.check_error, function() img:save(123) end, HERE,
                        "bad argument #1 to 'save'", "string expected, got number")
  os.remove("123")
  assert(ok, err)
end)

T.test("img:save encoding is one of 'srgb', 'linear'", function()
  local f = fixtures()
  T.check_error(function() f.img:save(f.png, {encoding = "sRGB"}) end, HERE,
                "bad argument #2 to 'save'", "field 'encoding'",
                "expected one of 'srgb', 'linear', got 'sRGB'")
  T.check_error(function() f.img:save(f.png, {encoding = "gamma"}) end, HERE,
                "bad argument #2 to 'save'", "field 'encoding'", "got 'gamma'")
  assert(not io.open(f.png, "rb"), "a failed save wrote " .. f.png)
end)

T.test("a closed image or scene raises instead of crashing", function()
  local s = lancer.scene{camera = CAMERA}
  local img = s:render{width = 2, height = 2}
  getmetatable(img).__close(img)
  T.eq(tostring(img), "lancer.Image (freed)", "tostring of a closed image")
  T.check_error(function() img:pixel(1, 1) end, HERE, "freed", "'pixel'")
  T.check_error(function() img:save("/nonexistent-lancer-test-dir/x.png") end, HERE,
                "freed", "'save'")
  T.check_error(function() return img.width end, HERE, "freed")
  getmetatable(s).__close(s)
  T.check_error(function() s:add(SPHERE) end, HERE, "freed", "'add'")
  T.check_error(function() s:render{width = 2, height = 2} end, HERE, "freed", "'render'")
  T.check_error(function() s.max_depth = 1 end, HERE, "freed")
end)

-- ---- failing calls leave the scene as it was (docs/numerics.md H25) ----------
local function small_scene()
  local s = lancer.scene{camera = lancer.camera{from = {0, 1.2, 4}, at = {0, 0.5, 0}},
                         ambient = 0.1, background = {0.1, 0.2, 0.3}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                     material = lancer.material{color = {0.8, 0.7, 0.6}, ka = 1}})
  s:add(lancer.sphere{center = {0, 0.6, 0}, radius = 0.6,
                      material = lancer.material{color = {0.9, 0.3, 0.2}, ks = 0.5,
                                                 kr = 0.3}})
  s:add(lancer.point_light{position = {2, 4, 3}, intensity = 20})
  return s
end
local OPTS = {width = 16, height = 12, seed = 7}

-- nil when a and b are bit-identical, else where they first differ.
local function differ(a, b)
  if a.width ~= b.width or a.height ~= b.height then
    return ("size %dx%d vs %dx%d"):format(a.width, a.height, b.width, b.height)
  end
  for y = 1, a.height do
    for x = 1, a.width do
      local r1, g1, b1 = a:pixel(x, y)
      local r2, g2, b2 = b:pixel(x, y)
      if r1 ~= r2 or g1 ~= g2 or b1 ~= b2 then
        return ("pixel (%d, %d): %.9g %.9g %.9g vs %.9g %.9g %.9g"):format(
          x, y, r1, g1, b1, r2, g2, b2)
      end
    end
  end
end

T.test("failing calls leave the scene unchanged (H25)", function()
  local s = small_scene()
  local first = s:render(OPTS)
  -- a sphere right in front of the camera, with a material the scene lacks
  local blocker = lancer.sphere{center = {0, 1.2, 3}, radius = 0.3,
                                material = lancer.material{color = {0, 1, 0}}}
  local bright = lancer.point_light{position = {0, 1, 1}, intensity = 100}
  local calls = {
    {"s:add(5)", function() s:add(5) end},
    {"s:add()", function() s:add() end},
    {"s:add(material)", function() s:add(MATERIAL) end},
    {"s:add(blocker, 5)", function() s:add(blocker, 5) end},
    {"s:add({blocker, 5})", function() s:add({blocker, 5}) end},
    {"s:add(bright, 'x')", function() s:add(bright, "x") end},
    {"s.background = -1", function() s.background = -1 end},
    {"s.background = {1, NaN, 1}", function() s.background = {1, NAN, 1} end},
    {"s.ambient = -1", function() s.ambient = -1 end},
    {"s.max_depth = -1", function() s.max_depth = -1 end},
    {"s.max_depth = 1.5", function() s.max_depth = 1.5 end},
    {"s.camera = 5", function() s.camera = 5 end},
    {"s.camera = material", function() s.camera = MATERIAL end},
    {"s.unknown = 1", function() s.unknown = 1 end},
    {"s:render{width = 0}", function() s:render{width = 0, height = 12} end},
    {"s:render{samples = 0}", function() s:render{width = 16, height = 12, samples = 0} end},
    {"s:render{seed = -1}", function() s:render{width = 16, height = 12, seed = -1} end},
    {"s:render{threads = -1}", function() s:render{width = 16, height = 12, threads = -1} end},
    {"s:render{cosine = 1}", function() s:render{width = 16, height = 12, cosine = 1} end},
    {"s:render{widht = 16}", function() s:render{widht = 16} end},
    {"s:render(5)", function() s:render(5) end},
  }
  local problems = {}
  local before = first
  for _, c in ipairs(calls) do
    local n0, l0 = s:count()
    local bg0, amb0, d0, cam0 = s.background, s.ambient, s.max_depth, s.camera
    local ok = pcall(c[2])
    local n1, l1 = s:count()
    if ok then problems[#problems + 1] = c[1] .. ": did not fail" end
    if n1 ~= n0 or l1 ~= l0 then
      problems[#problems + 1] = ("%s: counts went from %d shapes, %d lights to %d, %d")
        :format(c[1], n0, l0, n1, l1)
    end
    local bg1, amb1 = s.background, s.ambient
    for i = 1, 3 do
      if bg1[i] ~= bg0[i] or amb1[i] ~= amb0[i] then
        problems[#problems + 1] = c[1] .. ": background or ambient changed"
        break
      end
    end
    if s.max_depth ~= d0 then problems[#problems + 1] = c[1] .. ": max_depth changed" end
    if s.camera ~= cam0 then problems[#problems + 1] = c[1] .. ": camera changed" end
    local after = s:render(OPTS)
    local d = differ(before, after)
    if d then problems[#problems + 1] = c[1] .. ": image changed at " .. d end
    before = after
  end
  local d = differ(first, s:render(OPTS))
  if d then problems[#problems + 1] = "final image differs from the first at " .. d end
  assert(#problems == 0, "\n  " .. table.concat(problems, "\n  "))
end)

-- ---- bad values never crash ----------------------------------------------------
local GARBAGE = {
  {"nil", nil}, {"true", true}, {"'x'", "x"}, {"{}", {}}, {"{1, 2}", {1, 2}},
  {"{1, 2, 3, 4}", {1, 2, 3, 4}}, {"a function", function() end}, {"0/0", NAN},
  {"1/0", INF}, {"-1/0", -INF}, {"a coroutine", coroutine.create(function() end)},
}

-- What a failed call must look like; nil when fine.
local function bad_error(err, ...)
  if type(err) ~= "string" then return "raised a " .. type(err) .. ", not a string" end
  if not err:find(HERE, 1, true) then return "no position in this file: " .. err end
  for _, want in ipairs{...} do
    if want and not err:find(want, 1, true) then return "no " .. want .. " in: " .. err end
  end
end

local function report(problems, tried)
  assert(#problems == 0, ("%d of %d calls misbehaved:\n  "):format(#problems, tried)
    .. table.concat(problems, "\n  "))
end

for _, spec in ipairs(SPECS) do
  local name = spec.label or spec.fn
  T.test(name .. ": garbage in every field never crashes", function()
    local problems, tried = {}, 0
    local function try(what, arg, valid, want)
      tried = tried + 1
      local ok, err = pcall(CALL[spec.fn], arg)
      if ok and not valid then
        problems[#problems + 1] = what .. ": accepted"
      elseif not ok and valid then
        problems[#problems + 1] = what .. ": rejected a valid value: " .. tostring(err)
      elseif not ok then
        local why = bad_error(err, "'" .. spec.fn .. "'", want)
        if why then problems[#problems + 1] = what .. ": " .. why end
      end
    end
    for _, g in ipairs(GARBAGE) do
      local label, v = g[1], g[2]
      local valid = (v == nil and spec.nil_ok) or (label == "{}" and spec.empty_ok) or false
      try("whole argument " .. label, v, valid)
      for _, f in ipairs(spec.fields) do
        local field, kind, required = f[1], f[2], f[3]
        local ok_value = (v == nil and not required) or (v == true and kind == "bool")
        try(("%s = %s"):format(field, label), with(spec.base, field, v), ok_value,
            "'" .. field .. "'")
      end
      for _, field in ipairs(spec.other or {}) do
        try(("%s = %s"):format(field, label), with(spec.base, field, v), v == nil,
            "not both")
      end
    end
    report(problems, tried)
  end)
end

T.test("scene fields set to garbage never crash", function()
  local s = fixtures().scene
  local problems, tried = {}, 0
  for _, field in ipairs{"camera", "background", "ambient", "max_depth", "unknown"} do
    for _, g in ipairs(GARBAGE) do
      tried = tried + 1
      local ok, err = pcall(function() s[field] = g[2] end)
      if ok then
        problems[#problems + 1] = ("scene.%s = %s: accepted"):format(field, g[1])
      else
        local why = bad_error(err, "scene." .. field)
        if why then problems[#problems + 1] = ("scene.%s = %s: %s"):format(field, g[1], why) end
      end
    end
  end
  report(problems, tried)
end)

T.test("scene:add and img:pixel with garbage never crash", function()
  local s, img = lancer.scene{}, fixtures().img
  local problems, tried = {}, 0
  local function try(what, f, want)
    tried = tried + 1
    local ok, err = pcall(f)
    if ok then
      problems[#problems + 1] = what .. ": accepted"
    else
      local why = bad_error(err, want)
      if why then problems[#problems + 1] = what .. ": " .. why end
    end
  end
  for _, g in ipairs(GARBAGE) do
    local v = g[2]
    if g[1] ~= "{}" then     -- an empty array adds nothing, validly
      try("s:add(" .. g[1] .. ")", function() s:add(v) end, "'add'")
    end
    try("img:pixel(" .. g[1] .. ", 1)", function() img:pixel(v, 1) end, "'pixel'")
    try("img:pixel(1, " .. g[1] .. ")", function() img:pixel(1, v) end, "'pixel'")
  end
  T.eq(select(1, s:count()), 0, "shapes added by garbage")
  report(problems, tried)
end)

T.test("img:save with a garbage path never crashes", function()
  local img = fixtures().img
  local problems, tried = {}, 0
  for _, g in ipairs(GARBAGE) do
    local v = g[2]
    -- a string is a valid path; a number would be written under tostring(v)
    local as_file = type(v) == "number" and tostring(v) or nil
    if type(v) ~= "string" and not (as_file and io.open(as_file, "rb")) then
      tried = tried + 1
      local ok, err = pcall(function() img:save(v) end)
      if ok then
        problems[#problems + 1] = ("img:save(%s): accepted%s"):format(g[1],
          as_file and (", wrote a file named '" .. as_file .. "'") or "")
        if as_file then os.remove(as_file) end
      else
        local why = bad_error(err, "'save'")
        if why then problems[#problems + 1] = ("img:save(%s): %s"):format(g[1], why) end
      end
    end
  end
  report(problems, tried)
end)

-- A mirror bounce is a C recursion: a max_depth the API accepts must not
-- overflow the stack. Run in a child process so a crash cannot take the
-- test run down with it.
T.test("a max_depth the API accepts never crashes the renderer", function()
  local script = os.tmpname()
  local f = assert(io.open(script, "w"))
  f:write([[
local lancer = require "lancer"
local how, depth = arg[1], math.tointeger(tonumber(arg[2]))
local mirror = lancer.material{kd = 0, kr = 1}
local cam = lancer.camera{from = {0, 0, 0}, at = {0, 0, -1}}
local s
if how == "constructor" then
  s = lancer.scene{camera = cam, max_depth = depth}
else
  s = lancer.scene{camera = cam}
  s.max_depth = depth
end
-- two facing mirrors: the centre ray bounces until max_depth
s:add(lancer.plane{point = {0, 0, -1}, normal = {0, 0, 1}, material = mirror},
      lancer.plane{point = {0, 0, 1}, normal = {0, 0, -1}, material = mirror})
s:render{width = 1, height = 1, threads = 1}
]])
  f:close()
  local lo = 0
  while arg and arg[lo - 1] do lo = lo - 1 end
  local lua = arg and arg[lo] or "lua5.4"
  local function q(x) return "'" .. x:gsub("'", "'\\''") .. "'" end
  local problems = {}
  for _, how in ipairs{"setter", "constructor"} do
    local cmd = ("LUA_PATH=%s LUA_CPATH=%s timeout 120 %s %s %s 1000000"):format(
      q(package.path), q(package.cpath), q(lua), q(script), how)
    local _, err, code = T.run(cmd)
    if not (code == 0 or (code == 1 and err:find("max_depth", 1, true))) then
      problems[#problems + 1] = ("max_depth = 1000000 via the %s: exit code %d%s%s"):format(
        how, code, code == 139 and " (segmentation fault)" or "",
        err:find("%S") and (", stderr: " .. err:gsub("%s+$", "")) or "")
    end
  end
  os.remove(script)
  assert(#problems == 0, "\n  " .. table.concat(problems, "\n  "))
end)
