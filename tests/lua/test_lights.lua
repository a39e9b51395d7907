-- test_lights.lua: spot and directional lights, the sky as a background and
-- the tone curves in renders: each pixel against its closed form, the
-- effects they turn on (and only then), listing, moving, removing, scale
-- invariance, and every constructor's errors.
local T = require "harness"
local lancer = require "lancer"

local HERE = "test_lights.lua:"
local PI = math.pi

-- A camera looking straight down at the floor y = 0 from height 6.
local function floor_scene(extra)
  local s = lancer.scene{camera = lancer.camera{from = {0, 6, 0}, at = {0, 0, 0.0001},
                                                fov = 90}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}})
  for _, o in ipairs(extra or {}) do s:add(o) end
  return s
end

-- Every sampled pixel of a 1-spp render against want(point, pixel value).
local function each_pixel(s, W, H, step, check)
  local img = s:render{width = W, height = H}
  for y = 1, H, step do
    for x = 1, W, step do
      local tree = s:explain{x = x, y = y, width = W, height = H}
      check(tree.hit and tree.hit.point, x, y, img:pixel(x, y))
    end
  end
  return img
end

local function smoothstep_share(theta, angle, soft)
  local c, co, ci = math.cos(theta), math.cos(math.rad(angle)), math.cos(math.rad(angle - soft))
  if c >= ci then return 1 end
  if c <= co then return 0 end
  local t = (c - co) / (ci - co)
  return t * t * (3 - 2 * t)
end

T.test("a spot over a floor: intensity cos / d^2 times its cone's share, exactly", function()
  local h, I = 4, 16
  local spot = lancer.spot_light{position = {0, h, 0}, direction = {0, -1, 0}, angle = 45,
                                 soft = 15, intensity = I}
  local s = floor_scene{spot}
  local inside, edge, outside = 0, 0, 0
  each_pixel(s, 48, 48, 3, function(p, x, y, r, g, b)
    local rr = math.sqrt(p[1] ^ 2 + p[3] ^ 2)
    local d2 = h * h + rr * rr
    local theta = math.atan(rr, h)
    local share = smoothstep_share(theta, 45, 15)
    local want = I / d2 * share * h / math.sqrt(d2)
    T.near(r, want, 1e-6 * (1 + want), ("pixel %d,%d"):format(x, y))
    T.eq(g, r, "grey"); T.eq(b, r, "grey")
    if share == 1 then inside = inside + 1
    elseif share == 0 then outside = outside + 1; T.eq(r, 0, "outside is black")
    else edge = edge + 1 end
  end)
  assert(inside > 10 and edge > 10 and outside > 10, ("%d inside, %d on the edge, %d outside")
         :format(inside, edge, outside))
end)

T.test("a hard spot (soft = 0) with falloff 'none': a disc of exactly I cos", function()
  local h = 3
  local spot = lancer.spot_light{position = {0, h, 0}, at = {0, 0, 0}, angle = 30, soft = 0,
                                 intensity = 0.8, falloff = "none"}
  local s = floor_scene{spot}
  each_pixel(s, 40, 40, 3, function(p, x, y, r)
    local rr = math.sqrt(p[1] ^ 2 + p[3] ^ 2)
    local theta = math.atan(rr, h)
    if math.abs(theta - math.rad(30)) < 1e-9 then return end   -- the edge itself
    local want = theta < math.rad(30) and 0.8 * h / math.sqrt(h * h + rr * rr) or 0
    T.near(r, want, 1e-7, ("pixel %d,%d"):format(x, y))
  end)
end)

T.test("points outside a spot's cone trace no shadow ray", function()
  local spot = lancer.spot_light{position = {0, 4, 0}, direction = {0, -1, 0}, angle = 10,
                                 soft = 0, intensity = 16}
  local s = floor_scene{spot}
  local img, st = s:render{width = 32, height = 32}
  local lit = 0
  for y = 1, 32 do for x = 1, 32 do if img:pixel(x, y) > 0 then lit = lit + 1 end end end
  T.eq(st.rays.shadow, lit, "one shadow ray per lit pixel, none outside")
  assert(lit > 0 and lit < 32 * 32 / 4, "a small disc: " .. lit)
end)

T.test("a sun: irradiance cos / pi on a floor, with parallel shadows", function()
  local a = math.rad(60)
  local sun = lancer.directional_light{direction = {math.sin(a), -math.cos(a), 0},
                                       irradiance = 2, color = {1, 0.5, 0.25}}
  local c, rad = {0, 1.5, 0}, 1
  local s = floor_scene{sun}
  s:add(lancer.sphere{center = c, radius = rad})
  local lit, shadowed = 0, 0
  each_pixel(s, 48, 48, 2, function(p, x, y, r, g, b)
    if math.abs(p[2]) > 1e-9 then return end      -- the sphere, not the floor
    -- Toward the sun from p: does that line meet the sphere?
    local l = {-math.sin(a), math.cos(a), 0}
    local o = {p[1] - c[1], p[2] - c[2], p[3] - c[3]}
    local b2 = o[1] * l[1] + o[2] * l[2] + o[3] * l[3]
    local miss2 = (o[1] ^ 2 + o[2] ^ 2 + o[3] ^ 2) - b2 * b2
    if math.abs(math.sqrt(miss2) - rad) < 1e-6 then return end  -- the shadow's edge
    local blocked = miss2 < rad * rad and b2 < 0
    local want = blocked and 0 or 2 * math.cos(a) / PI
    T.near(r, want, 1e-7, ("r at %d,%d"):format(x, y))
    T.near(g, want * 0.5, 1e-7, "g"); T.near(b, want * 0.25, 1e-7, "b")
    if blocked then shadowed = shadowed + 1 else lit = lit + 1 end
  end)
  assert(lit > 20 and shadowed > 20, ("%d lit, %d shadowed"):format(lit, shadowed))
end)

T.test("a sun behind the surface lights nothing and casts no ray", function()
  local sun = lancer.directional_light{direction = {0, 1, 0}, irradiance = 5}
  local img, st = floor_scene{sun}:render{width = 8, height = 8}
  T.eq(st.rays.shadow, 0, "shadow rays")
  T.eq(img:pixel(4, 4), 0, "black")
end)

T.test("spot and sun are effects only when present, with a ledger row each", function()
  local s = floor_scene{lancer.point_light{position = {0, 3, 0}, intensity = 9}}
  local _, st = s:render{width = 8, height = 8}
  T.eq(st.effects.spot, false, "spot"); T.eq(st.effects.sun, false, "sun")
  T.eq(st.effects.sky, false, "sky")
  T.eq(st.why.spot, "no spot light"); T.eq(st.why.sun, "no directional light")
  T.eq(st.why.sky, "the background is one colour")
  s:add(lancer.spot_light{position = {0, 3, 0}, at = {0, 0, 0}},
        lancer.directional_light{direction = {0, -1, 0}})
  _, st = s:render{width = 8, height = 8}
  T.eq(st.effects.spot, true, "spot"); T.eq(st.effects.sun, true, "sun")
  local ledger = lancer.ledger(st)
  assert(ledger:find("on  spot      1 spot light", 1, true), ledger)
  assert(ledger:find("on  sun       1 directional light", 1, true), ledger)
  assert(ledger:find("off sky       the background is one colour", 1, true), ledger)
  -- Unlit materials: defined lights, no effect.
  local dark = lancer.scene{camera = lancer.camera{from = {0, 6, 0}, at = {0, 0, 0.0001}}}
  dark:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                        material = lancer.material{kd = 0, ka = 1}},
           lancer.spot_light{position = {0, 3, 0}, at = {0, 0, 0}})
  _, st = dark:render{width = 8, height = 8}
  T.eq(st.effects.spot, false, "spot over kd = 0")
  T.eq(st.why.spot, "no material in use has kd or ks > 0")
end)

T.test("a spot and a sun add to a point light as their parts do, within float rounding", function()
  local p = lancer.point_light{position = {1, 3, -1}, intensity = 9}
  local sp = lancer.spot_light{position = {0, 4, 0}, at = {0, 0, 0}, intensity = 16}
  local sun = lancer.directional_light{direction = {0.3, -1, 0.2}, irradiance = 1}
  local mat = lancer.material{color = {0.9, 0.6, 0.3}, ks = 0.5, alpha = 20}
  local function render(lights)
    local s = lancer.scene{camera = lancer.camera{from = {0, 6, -3}, at = {0, 0, 0}}}
    s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}, material = mat})
    s:add(lancer.sphere{center = {0, 1, 0}, radius = 1, material = mat})
    for _, l in ipairs(lights) do s:add(l) end
    return (s:render{width = 24, height = 16})
  end
  local all, a, b, c = render{p, sp, sun}, render{p}, render{sp}, render{sun}
  local sum = lancer.image{width = 24, height = 16}:add(a):add(b):add(c)
  -- Light colours add in double before the image's float: within float
  -- rounding of values up to about 4 (three roundings of 4.8e-7).
  assert(all:diff(sum).max <= 1.5e-6, "max " .. all:diff(sum).max)
  assert(all:diff(a).max > 0.01, "the spot and sun show")
end)

T.test("spot and directional lights list, move, remove and scale like point lights", function()
  local s = floor_scene()
  local sp = lancer.spot_light{position = {1, 4, 2}, direction = {0, -2, 0}, angle = 20,
                               soft = 4, color = {1, 0.5, 0.5}, intensity = 8}
  local sun = lancer.directional_light{direction = {0, -1, 1}, irradiance = 3}
  s:add(sp, sun)
  local objs = s:objects()
  T.eq(#objs, 3, "objects")
  T.eq(objs[2].kind, "spot_light"); T.eq(objs[3].kind, "directional_light")
  T.eq(tostring(objs[2]), "#2 lancer.spot_light{position = {1, 4, 2}, direction = " ..
       "{0, -2, 0}, angle = 20, soft = 4, color = {1, 0.5, 0.5}, intensity = 8, " ..
       "falloff = 'inverse_square'}")
  T.eq(tostring(objs[3]), "#3 lancer.directional_light{direction = {0, -1, 1}, " ..
       "irradiance = 3, color = {1, 1, 1}}")
  T.eq(sp.angle, 20); T.eq(sp.soft, 4); T.eq(sun.irradiance, 3); T.eq(sp.direction[2], -2)
  -- Moved: position by the whole map, directions by its linear part.
  local m = sp:moved(lancer.rotate("x", 90) * lancer.translate(0, 1, 0))
  local mp, md = m.position, m.direction
  T.near(mp[1], 1, 1e-12); T.near(mp[2], -2, 1e-12); T.near(mp[3], 5, 1e-12)
  T.near(md[1], 0, 1e-12); T.near(md[2], 0, 1e-12); T.near(md[3], -2, 1e-12)
  local ms = sun:moved(lancer.translate(5, 5, 5))
  T.eq(ms.direction[3], 1, "a translation leaves a sun alone")
  local g = lancer.group{sp}:moved(lancer.translate(0, 1, 0))
  s:add(g)
  T.eq(s:objects()[4].object.position[2], 5, "moved in a group")
  s:remove(sp)
  s:remove(3)
  T.eq(#s:objects(), 2, "removed")
  T.eq(s:objects()[2].kind, "spot_light")
  local n, lights = s:count()
  T.eq(lights, 1, "lights counted")
end)

T.test("a spot-lit and sun-lit scene is the same at scales 1e-3..1e3 and 1e6 away", function()
  local s = lancer.scene{camera = lancer.camera{from = {0, 3, -5}, at = {0, 0.5, 0}}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}},
        lancer.sphere{center = {0, 1, 0}, radius = 1},
        lancer.spot_light{position = {2, 4, -2}, at = {0, 0, 0}, angle = 25, intensity = 20},
        lancer.directional_light{direction = {-1, -2, 1}, irradiance = 1})
  local ref = s:render{width = 48, height = 36}
  for _, v in ipairs{{1e-3, {0, 0, 0}}, {1e3, {0, 0, 0}}, {1, {1e6, 0, 0}}} do
    local img = s:transformed(v[1], v[2]):render{width = 48, height = 36}
    local d = img:diff(ref)
    assert(d.within >= 0.999, ("scale %g: %.4f within 1/255"):format(v[1], d.within))
  end
end)

T.test("explain names spot and directional lights", function()
  local s = floor_scene{lancer.spot_light{position = {0, 3, 0}, at = {0, 0, 0}},
                        lancer.directional_light{direction = {0, -1, 0}, irradiance = PI}}
  local tree = s:explain{x = 8, y = 8, width = 16, height = 16}
  T.eq(tree.rays[1].light, "spot light 1")
  T.eq(tree.rays[2].light, "directional light 1")
  T.near(tree.rays[2].contribution[1], 1, 1e-7, "a sun of irradiance pi facing it: 1")
  assert(tostring(tree):find("shadow to directional light 1: visible", 1, true))
end)

-- ---- the sky ---------------------------------------------------------------------

T.test("a sky gradient: each pixel the colour its direction's height gives", function()
  local sky = lancer.sky{zenith = {0.1, 0.3, 0.9}, horizon = {1, 0.9, 0.8},
                         ground = {0.3, 0.25, 0.2}}
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, 0}, at = {0.2, 0.1, 1},
                                                fov = 120}, background = sky}
  T.eq(s.background, sky, "reads back")
  local img, st = s:render{width = 40, height = 30}
  T.eq(st.effects.sky, true); T.eq(st.why.sky, "the background is a texture over directions")
  local zen, hor, gnd = {0.1, 0.3, 0.9}, {1, 0.9, 0.8}, {0.3, 0.25, 0.2}
  for y = 1, 30, 3 do
    for x = 1, 40, 3 do
      local tree = s:explain{x = x, y = y, width = 40, height = 30}
      local d = tree.direction
      local yy = d[2] / math.sqrt(d[1] ^ 2 + d[2] ^ 2 + d[3] ^ 2)
      local px = {img:pixel(x, y)}
      for k = 1, 3 do
        local want = yy >= 0 and hor[k] + (zen[k] - hor[k]) * yy
                             or hor[k] + (gnd[k] - hor[k]) * -yy
        T.near(px[k], want, 2e-7, ("channel %d at %d,%d"):format(k, x, y))
      end
    end
  end
end)

T.test("an image as the background: an equirectangular map, texel for texel", function()
  -- 8x4 texels, each its own colour; looking along the centre of texel
  -- (i, j) reads it exactly (nearest filter).
  local W, H = 8, 4
  local map = lancer.image{width = W, height = H}
  for j = 1, H do for i = 1, W do map:set(i, j, i / 8, j / 4, (i * j % 5) / 5) end end
  local tex = lancer.image_texture{image = map, filter = "nearest"}
  for j = 1, H do
    for i = 1, W do
      local u, v = (i - 0.5) / W, 1 - (j - 0.5) / H
      local lon, lat = (u - 0.5) * 2 * PI, (v - 0.5) * PI
      local d = {math.cos(lat) * math.sin(lon), math.sin(lat), math.cos(lat) * math.cos(lon)}
      local s = lancer.scene{camera = lancer.camera{from = {0, 0, 0}, at = d, fov = 1},
                             background = tex}
      local r, g, b = s:render{width = 1, height = 1}:pixel(1, 1)
      T.near(r, i / 8, 1e-7, ("r of texel %d,%d"):format(i, j))
      T.near(g, j / 4, 1e-7, "g"); T.near(b, (i * j % 5) / 5, 1e-7, "b")
    end
  end
end)

T.test("a mirror reflects the sky; a colour again turns the sky off", function()
  local sky = lancer.sky{zenith = {0, 0, 1}, horizon = {1, 1, 1}}
  local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 0, 0}},
                         background = sky}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                     material = lancer.material{kd = 0, kr = 1}})
  local img = s:render{width = 16, height = 16}
  -- The floor mirrors the direction upward: a reflected ray of height y
  -- reads the zenith's blend at y.
  local tree = s:explain{x = 8, y = 14, width = 16, height = 16}
  local d = tree.rays[1].direction
  local yy = d[2] / math.sqrt(d[1] ^ 2 + d[2] ^ 2 + d[3] ^ 2)
  local r, g, b = img:pixel(8, 14)
  T.near(r, 1 - yy, 2e-7, "r"); T.near(b, 1, 2e-7, "b")
  -- Back to a colour: the texture is gone, the colour renders as before.
  s.background = {0.2, 0.3, 0.4}
  T.eq(type(s.background), "table")
  local _, st = s:render{width = 4, height = 4}
  T.eq(st.effects.sky, false, "sky off again")
end)

T.test("a sky background survives scene:transformed (directions do not move)", function()
  local sky = lancer.sky{zenith = {0.2, 0.4, 1}, horizon = {1, 1, 1}, ground = {0.1, 0.1, 0.1}}
  local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 1, 0}},
                         background = sky}
  s:add(lancer.sphere{center = {0, 1, 0}, radius = 1,
                      material = lancer.material{kd = 0, kr = 0.9}})
  local ref = s:render{width = 32, height = 24}
  local far = s:transformed(1e3, {1e6, 0, 0})
  T.eq(far.background, sky, "the copy has the sky")
  assert(far:render{width = 32, height = 24}:diff(ref).within >= 0.999, "same picture")
end)

-- ---- tone ------------------------------------------------------------------------

local function saved_values(img, opts)
  local path = os.tmpname() .. ".png"
  opts.encoding = "linear"
  img:save(path, opts)
  local back = lancer.load_png(path, {encoding = "linear"})
  os.remove(path)
  local out = {}
  for x = 1, img.width do out[x] = math.floor(back:pixel(x, 1) * 255 + 0.5) end
  return out
end

T.test("save's exposure and filmic curve: round(255 f(2^e x)) per channel", function()
  local xs = {0, 0.05, 0.18, 0.5, 1, 2, 4, 16}
  local img = lancer.image{width = #xs, height = 1}
  for i, x in ipairs(xs) do img:set(i, 1, x, x, x) end
  local function filmic(x)
    local y = x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)
    return math.min(1, math.max(0, y))
  end
  local got = saved_values(img, {tone = "filmic"})
  for i, x in ipairs(xs) do T.eq(got[i], math.floor(filmic(x) * 255 + 0.5), "filmic " .. x) end
  got = saved_values(img, {tone = "filmic", exposure = -1})
  for i, x in ipairs(xs) do
    T.eq(got[i], math.floor(filmic(x / 2) * 255 + 0.5), "filmic at -1 stop, " .. x)
  end
  got = saved_values(img, {exposure = 2})
  for i, x in ipairs(xs) do
    T.eq(got[i], math.floor(math.min(1, 4 * x) * 255 + 0.5), "clamp at +2 stops, " .. x)
  end
end)

T.test("save with exposure 0 and tone 'clamp' writes the same bytes as without", function()
  local img = lancer.image{width = 3, height = 2, color = {0.3, 1.7, 0.01}}
  img:set(2, 2, 0.5, 0.25, 0.125)
  local a, b = os.tmpname() .. ".png", os.tmpname() .. ".png"
  img:save(a)
  img:save(b, {exposure = 0, tone = "clamp"})
  local fa, fb = io.open(a, "rb"), io.open(b, "rb")
  local da, db = fa:read("a"), fb:read("a")
  fa:close(); fb:close(); os.remove(a); os.remove(b)
  T.eq(da == db, true, "same bytes")
end)

-- ---- errors ----------------------------------------------------------------------

T.test("spot, directional and sky constructors and save options raise naming the field",
function()
  local C = T.check_error
  C(function() lancer.spot_light{direction = {0, -1, 0}} end,
    HERE, "'spot_light'", "field 'position'")
  C(function() lancer.spot_light{position = {0, 1, 0}} end,
    HERE, "'spot_light'", "field 'direction'", "required")
  C(function() lancer.spot_light{position = {0, 1, 0}, direction = {0, -1, 0}, at = {0, 0, 0}} end,
    HERE, "field 'at'", "give one of them")
  C(function() lancer.spot_light{position = {0, 1, 0}, at = {0, 1, 0}} end,
    HERE, "field 'at'", "must differ from 'position'")
  C(function() lancer.spot_light{position = {0, 1, 0}, direction = {0, 0, 0}} end,
    HERE, "field 'direction'", "zero-length")
  C(function() lancer.spot_light{position = {0, 1, 0}, direction = {0, 0 / 0, 0}} end,
    HERE, "field 'direction'", "NaN")
  C(function() lancer.spot_light{position = {0, 1, 0}, direction = {0, -1, 0}, angle = 0 / 0} end,
    HERE, "field 'angle'", "NaN")
  C(function() lancer.spot_light{position = {0, 1, 0}, direction = {0, -1, 0}, angle = 180} end,
    HERE, "field 'angle'", "got 180")
  C(function() lancer.spot_light{position = {0, 1, 0}, direction = {0, -1, 0}, angle = 20,
                                 soft = 25} end,
    HERE, "field 'soft'", "must be in [0, angle]", "got 25")
  C(function() lancer.spot_light{position = {0, 1, 0}, direction = {0, -1, 0}, soft = -1} end,
    HERE, "field 'soft'", "got -1")
  C(function() lancer.spot_light{position = {0, 1, 0}, direction = {0, -1, 0}, angle = "wide"} end,
    HERE, "field 'angle'", "number expected, got string")
  C(function() lancer.spot_light{position = {0, 1, 0}, direction = {0, -1, 0}, intensity = -3} end,
    HERE, "field 'intensity'", "got -3")
  C(function() lancer.spot_light{position = {0, 1, 0}, direction = {0, -1, 0}, falloff = "linear"} end,
    HERE, "field 'falloff'", "'inverse_square'")
  C(function() lancer.spot_light{position = {0, 1, 0}, direction = {0, -1, 0}, angel = 3} end,
    HERE, "unknown field 'angel'", "did you mean 'angle'?")
  C(function() lancer.directional_light{irradiance = 1} end,
    HERE, "'directional_light'", "field 'direction'")
  C(function() lancer.directional_light{direction = {0, -1, 0}, irradiance = -1} end,
    HERE, "field 'irradiance'", "got -1")
  C(function() lancer.directional_light{direction = {0, -1, 0}, irradiance = 0 / 0} end,
    HERE, "field 'irradiance'")
  C(function() lancer.directional_light{direction = {0, -1, 0}, color = {1, -1, 1}} end,
    HERE, "field 'color'")
  C(function() lancer.directional_light{direction = {1, 0, 0}, position = {0, 0, 0}} end,
    HERE, "unknown field 'position'")
  C(function() lancer.sky{horizon = {1, 1, 1}} end, HERE, "'sky'", "field 'zenith'")
  C(function() lancer.sky{zenith = {0, 0, 1}} end, HERE, "'sky'", "field 'horizon'")
  C(function() lancer.sky{zenith = "blue", horizon = 1} end, HERE, "field 'zenith'")
  C(function() lancer.sky{zenith = 1, horizon = 1, ground = {0 / 0, 0, 0}} end,
    HERE, "field 'ground'")
  C(function() lancer.sky{zenith = 1, horizon = 1, grund = 0} end,
    HERE, "unknown field 'grund'", "did you mean 'ground'?")
  local img = lancer.image{width = 1, height = 1}
  C(function() img:save("x.png", {exposure = 0 / 0}) end, HERE, "'save'", "field 'exposure'")
  C(function() img:save("x.png", {exposure = 100}) end, HERE, "field 'exposure'", "[-64, 64]")
  C(function() img:save("x.png", {exposure = "bright"}) end, HERE, "field 'exposure'",
    "number expected, got string")
  C(function() img:save("x.png", {tone = "aces"}) end, HERE, "field 'tone'", "'clamp'",
    "'filmic'")
  C(function() lancer.scene{background = "sky"} end, HERE, "'scene'", "field 'background'")
  local s = lancer.scene{}
  C(function() s.background = true end, HERE, "scene.background", "or a texture")
end)
