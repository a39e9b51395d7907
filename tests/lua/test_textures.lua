-- test_textures.lua: textured materials in renders: closed forms on a
-- checker floor, an image reproduced texel for texel, effects on demand,
-- object space, scale invariance, and the constructors' errors.
local T = require "harness"
local lancer = require "lancer"

local HERE = "test_textures.lua:"

-- Ambient light only (ka = 1, kd = 0): a pixel reads the colour itself.
local function flat(color)
  return lancer.material{color = color, ka = 1, kd = 0}
end

T.test("a checker floor: each pixel the colour of the square its ray lands on", function()
  local checker = lancer.checker{a = {0.8, 0.6, 0.4}, b = {0.1, 0.2, 0.3}, scale = 0.5}
  local s = lancer.scene{camera = lancer.camera{from = {0.3, 3, 0.2}, at = {0.3, 0, 0.2001},
                                                fov = 60}, ambient = 1}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}, material = flat(checker)})
  local W, H = 48, 36
  local img = s:render{width = W, height = H}
  -- Where each pixel's camera ray lands: explain's record of it.
  local seen = {a = 0, b = 0}
  for y = 1, H, 7 do
    for x = 1, W, 5 do
      local tree = s:explain{x = x, y = y, width = W, height = H}
      local p = tree.hit.point
      local sum = math.floor(p[1] / 0.5) + math.floor(p[2] / 0.5) + math.floor(p[3] / 0.5)
      local want = sum % 2 == 0 and {0.8, 0.6, 0.4} or {0.1, 0.2, 0.3}
      local pr, pg, pb = img:pixel(x, y)
      T.near(pr, want[1], 1e-6, ("r at %d,%d"):format(x, y))
      T.near(pg, want[2], 1e-6, ("g at %d,%d"):format(x, y))
      T.near(pb, want[3], 1e-6, ("b at %d,%d"):format(x, y))
      seen[sum % 2 == 0 and "a" or "b"] = seen[sum % 2 == 0 and "a" or "b"] + 1
    end
  end
  assert(seen.a > 5 and seen.b > 5, "both squares seen")
end)

T.test("an image texture on a quad filling the frame reproduces it texel for texel", function()
  local W, H = 12, 8
  local src = lancer.image{width = W, height = H}
  for y = 1, H do
    for x = 1, W do src:set(x, y, (x - 1) / 16, (y - 1) / 16, ((x * y) % 7) / 7) end
  end
  -- A pinhole at z = -1 looking at the quad z = 0 spanning exactly the
  -- frustum: pixel centres land on texel centres.
  local tx = math.tan(math.rad(60) / 2)
  local hw, hh = tx, tx * H / W
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, -1}, at = {0, 0, 0}, fov = 60},
                         ambient = 1}
  local tex = lancer.image_texture{image = src}
  -- Looking along +z, +x is on the left: the quad's corner (u = 0) at the
  -- image's bottom-left is at x = +hw, its u edge toward -x.
  s:add(lancer.quad{corner = {hw, -hh, 0}, u = {-2 * hw, 0, 0}, v = {0, 2 * hh, 0},
                    material = flat(tex)})
  local img = s:render{width = W, height = H}
  local d = img:diff(src, 0)
  T.eq(d.max, 0, "every channel of every pixel exactly the texel's")
end)

T.test("effects on demand: an unused textured material changes nothing", function()
  local function scene(extra)
    local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 0.5, 0}},
                           ambient = 0.1}
    s:add(lancer.sphere{center = {0, 0.5, 0}, radius = 0.5,
                        material = lancer.material{color = {0.7, 0.3, 0.2}, ks = 0.3}})
    s:add(lancer.point_light{position = {2, 3, -2}, intensity = 10})
    if extra then
      -- a textured material that no shape uses: registered, never evaluated
      s:add(lancer.sphere{center = {0, -100, 0}, radius = 1,
                          material = lancer.material{color = lancer.checker{}}})
    end
    return s
  end
  local a, sa = scene(false):render{width = 32, height = 24}
  local b, sb = scene(true):render{width = 32, height = 24}
  T.eq(sa.effects.texture, false, "no texture: the effect is off")
  T.eq(sb.effects.texture, true, "a textured sphere out of view: on")
  T.eq(a:diff(b, 0).max, 0, "the same bits where the textured sphere is not seen")
  T.eq(sa.why.texture, "no material in use has a texture", "why")
end)

T.test("object space follows a moved mesh; world space stays put", function()
  local quad = lancer.mesh{vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}},
                           faces = {{1, 2, 3, 4}}}
  local function color_at(mapping, shift)
    local stripes = lancer.stripes{a = {1, 0, 0}, b = {0, 0, 1}, scale = 0.5,
                                   mapping = mapping}
    local m = lancer.mesh{vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}},
                          faces = {{1, 2, 3, 4}}, material = flat(stripes)}
    local s = lancer.scene{camera = lancer.camera{from = {0.25 + shift, 0.5, -2},
                                                  at = {0.25 + shift, 0.5, 0}}, ambient = 1}
    s:add(m:moved(lancer.translate(shift, 0, 0)))
    local img = s:render{width = 1, height = 1}
    return {img:pixel(1, 1)}
  end
  -- The camera looks at the mesh's own x = 0.25 (stripe 0) wherever it is.
  T.eq(color_at("object", 0)[1], 1, "object space, in place: stripe 0")
  T.eq(color_at("object", 0.5)[1], 1, "object space, moved by a stripe: still stripe 0")
  T.eq(color_at("world", 0.5)[3], 1, "world space, moved: world x = 0.75, stripe 1")
  local _ = quad
end)

T.test("H1 with textures: a scaled scene renders the same", function()
  local s = lancer.scene{camera = lancer.camera{from = {0, 2, -5}, at = {0, 0.5, 0}},
                         ambient = 0.2}
  local floor = lancer.checker{a = {0.9, 0.9, 0.9}, b = {0.2, 0.2, 0.2}, scale = 0.7}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                     material = lancer.material{color = floor}})
  s:add(lancer.sphere{center = {0, 0.6, 0}, radius = 0.6,
                      material = lancer.material{color = lancer.marble{scale = 0.4}}})
  s:add(lancer.point_light{position = {2, 4, -3}, intensity = 20})
  local a = s:render{width = 40, height = 30}
  for _, k in ipairs{0.001, 1000} do
    local b = s:transformed(k, {3, -2, 1}):render{width = 40, height = 30}
    local d = a:diff(b, 1 / 255)
    assert(d.within >= 0.99, ("scale %g: %.2f%% of pixels within 1/255"):format(
      k, 100 * d.within))
  end
end)

T.test("textures: every constructor's fields checked, in Lua's voice", function()
  local cases = {
    {function() lancer.checker{scale = 0} end, "'checker'", "field 'scale'"},
    {function() lancer.checker{a = "red"} end, "'checker'", "field 'a'"},
    {function() lancer.checker{scael = 1} end, "'checker'", "scael", "scale"},
    {function() lancer.stripes{axis = {0, 0, 0}} end, "'stripes'", "field 'axis'",
     "zero-length"},
    {function() lancer.noise{octaves = 0} end, "'noise'", "field 'octaves'", "[1, 16]"},
    {function() lancer.noise{octaves = 17} end, "'noise'", "field 'octaves'"},
    {function() lancer.marble{turbulence = -1} end, "'marble'", "field 'turbulence'"},
    {function() lancer.wood{scale = 0 / 0} end, "'wood'", "field 'scale'"},
    {function() lancer.mix{amount = 2} end, "'mix'", "field 'amount'", "[0, 1]"},
    {function() lancer.mix{amount = "half"} end, "'mix'", "field 'amount'"},
    {function() lancer.gradient{from = {0, 0, 0}, to = {0, 0, 0}} end, "'gradient'",
     "field 'axis'"},
    {function() lancer.checker{mapping = "uvw"} end, "'checker'", "field 'mapping'"},
    {function() lancer.image_texture{} end, "'image_texture'", "field 'image'"},
    {function() lancer.image_texture{path = "/nonexistent.png"} end, "'image_texture'",
     "field 'path'", "cannot open"},
    {function() lancer.image_texture{image = lancer.image{width = 1, height = 1},
                                     wrap = "tile"} end, "'image_texture'", "field 'wrap'"},
    {function() lancer.material{bump = 3} end, "'material'", "field 'bump'",
     "a texture"},
    {function() lancer.material{bump = lancer.noise{}, bump_scale = 1 / 0} end,
     "'material'", "field 'bump_scale'"},
  }
  for i, c in ipairs(cases) do
    local ok, msg = pcall(c[1])
    assert(not ok, "case " .. i .. ": no error")
    for k = 2, #c do
      assert(tostring(msg):find(c[k], 1, true), ("case %d: %q not in %s"):format(i, c[k], msg))
    end
    assert(tostring(msg):find(HERE, 1, true), ("case %d: not at the caller: %s"):format(i, msg))
  end
end)

T.test("textures nest, and a material reads its textured fields back", function()
  local inner = lancer.checker{a = {1, 0, 0}, b = {0, 1, 0}}
  local outer = lancer.mix{a = inner, b = {0, 0, 1}, amount = lancer.gradient{}}
  local m = lancer.material{color = outer, kd = lancer.noise{}, bump = lancer.noise{}}
  T.eq(m.color, outer, "color reads as its texture")
  T.eq(m.kd.kind, "noise", "kd too")
  T.eq(m.bump_scale, 1, "bump_scale defaults to 1 with a bump")
  T.eq(outer.kind, "mix", "kind")
  local moved = inner:moved(lancer.translate(1, 0, 0))
  T.eq(tostring(moved), "lancer.checker{...} moved", "moved")
  -- One texture shared by two materials is added to the scene once.
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, -3}, at = {0, 0, 0}},
                         ambient = 1}
  s:add(lancer.sphere{center = {-1, 0, 0}, radius = 0.5, material = flat(inner)},
        lancer.sphere{center = {1, 0, 0}, radius = 0.5, material = flat(inner)},
        lancer.sphere{center = {0, 1, 0}, radius = 0.5, material = m})
  local _, st = s:render{width = 8, height = 8}
  T.eq(st.effects.texture, true, "rendered")
end)
