-- test_effects.lua: only the effects a scene calls for run (docs/numerics.md 4.3:
-- S1-S4, S6, S8, S10, exact ray counts), switches, the ledger, explain.
local T = require "harness"
local lancer = require "lancer"

local W, H = 24, 16

-- Looking straight down at a plane: every camera ray hits it, and it faces
-- every light above it.
local function plane_scene(materials)
  local s = lancer.scene{camera = lancer.camera{from = {0, 5, 0}, at = {0, 0, 0},
                                                up = {0, 0, 1}, fov = 40}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                     material = materials and materials.floor})
  return s
end

local function same(a, b, what)
  local d = a:diff(b, 0)
  assert(d.max == 0, ("%s: images differ by %g at (%d, %d)"):format(what, d.max,
                                                                  d.worst_x, d.worst_y))
end

T.test("S1 camera rays are exactly width x height x samples", function()
  local s = plane_scene()
  for _, spp in ipairs{1, 4, 9, 5} do
    local _, st = s:render{width = W, height = H, samples = spp}
    T.eq(st.rays.camera, W * H * spp, "camera rays at " .. spp .. " spp")
  end
end)

T.test("S2 a diffuse-only scene: no reflection ray; shadow = W*H*spp*lights", function()
  local s = plane_scene()
  s:add(lancer.point_light{position = {1, 4, 0}, intensity = 10})
  s:add(lancer.point_light{position = {-1, 3, 1}, intensity = 10})
  s:add(lancer.point_light{position = {0, 6, -2}, intensity = 10})
  local _, st = s:render{width = W, height = H, samples = 4}
  T.eq(st.rays.shadow, W * H * 4 * 3, "shadow rays")
  T.eq(st.rays.reflection, 0, "reflection rays")
  T.eq(st.rays.cut, 0, "cut rays")
  T.eq(st.effects.reflect, false, "reflect effect")
  T.eq(st.effects.specular, false, "specular effect")
  T.eq(st.why.reflect, "no material in use has kr > 0", "why no reflection")
end)

T.test("S3 no lights: no shadow ray, and the image is ambient and emission only", function()
  local s = plane_scene{floor = lancer.material{color = {0.5, 0.25, 1}, ks = 1, kr = 0.5,
                                                emission = 0.125}}
  s.ambient = 0.5
  local img, st = s:render{width = W, height = H}
  T.eq(st.rays.shadow, 0, "shadow rays")
  T.eq(st.effects.shadow, false, "shadow effect")
  T.eq(st.why.shadow, "no point light", "why no shadows")
  -- kr 0.5 toward a black sky: colour * (ka Ia) + emission.
  local r, g, b = img:pixel(W // 2, H // 2)
  T.near(r, 0.5 * 0.5 + 0.125, 1e-6, "red")
  T.near(g, 0.25 * 0.5 + 0.125, 1e-6, "green")
  T.near(b, 1 * 0.5 + 0.125, 1e-6, "blue")
end)

T.test("S4 effects follow coefficients, not names: kr = 0 gives 0 reflection rays", function()
  local black_mirror = lancer.material{color = 0, kd = 0, kr = 0, ks = 0}
  local s = plane_scene{floor = black_mirror}
  s:add(lancer.point_light{position = {0, 4, 0}, intensity = 10})
  local _, st = s:render{width = W, height = H}
  T.eq(st.rays.reflection, 0, "reflection rays")
  T.eq(st.rays.shadow, 0, "a material with kd = ks = 0 needs no light")
  T.eq(st.effects.shadow, false, "shadow effect")
end)

T.test("S6 switches: shadows, reflections, specular off show in the counts", function()
  local m = lancer.material{kd = 0.5, ks = 0.5, alpha = 10, kr = 0.5}
  local s = plane_scene{floor = m}
  s:add(lancer.sphere{center = {0, 1, 0}, radius = 0.5, material = m})
  s:add(lancer.point_light{position = {0.3, 4, 0.2}, intensity = 10})
  local _, on = s:render{width = W, height = H}
  assert(on.rays.shadow > 0 and on.rays.reflection > 0, "both kinds when on")
  local _, st = s:render{width = W, height = H, shadows = false}
  T.eq(st.rays.shadow, 0, "shadows = false: no shadow ray")
  T.eq(st.rays.reflection, on.rays.reflection, "reflections unchanged")
  _, st = s:render{width = W, height = H, reflections = false}
  T.eq(st.rays.reflection, 0, "reflections = false")
  T.eq(st.effects.reflect, false, "reflect effect")
  T.eq(st.why.reflect, "switched off (reflections = false)", "why")
  _, st = s:render{width = W, height = H, specular = false}
  T.eq(st.effects.specular, false, "specular effect")
  -- shadows = false: the shadowed floor under the sphere is lit as if nothing
  -- were in the way: kd * C * I * cos / d^2 straight below the light.
  local img = s:render{width = W, height = H, shadows = false, reflections = false,
                       specular = false}
  local lit = s:render{width = W, height = H, reflections = false, specular = false}
  assert(img:diff(lit, 0).max > 0, "the shadow is gone")
  -- point lights only: no emitter effect and no emitter shadow ray
  T.eq(on.effects.emitter, false, "emitter effect")
  T.eq(on.why.emitter, "no emissive shape", "why no emitter")
end)

T.test("S8 unused materials and lights cost nothing: same rays, same image", function()
  local s1 = plane_scene()
  s1:add(lancer.point_light{position = {0, 4, 0}, intensity = 10})
  local s2 = plane_scene()
  s2:add(lancer.point_light{position = {0, 4, 0}, intensity = 10})
  -- defined, never added to a shape: a mirror, a highlight, a glow
  local _ = {lancer.material{kr = 1}, lancer.material{ks = 1, alpha = 50},
             lancer.material{emission = 5}}
  local a, sa = s1:render{width = W, height = H}
  local b, sb = s2:render{width = W, height = H}
  same(a, b, "unused materials")
  for _, k in ipairs{"camera", "shadow", "reflection", "cut"} do
    T.eq(sb.rays[k], sa.rays[k], k .. " rays")
  end
  T.eq(sb.prim_tests, sa.prim_tests, "primitive tests")
  T.eq(sb.effects.reflect, false, "reflect effect")
  T.eq(sb.effects.emitter, false, "emitter effect")
end)

-- Scenes that use every effect, for S10; without mirrors and highlights
-- (mirrors = false), the scenes the diffuse copy of the path loop draws.
local function rich_scene(mirrors)
  local kr, ks = mirrors and 0.2 or 0, mirrors and 0.6 or 0
  local s = lancer.scene{camera = lancer.camera{from = {0, 1.5, -5}, at = {0, 0.8, 0}},
                         ambient = 0.05, background = {0.1, 0.2, 0.3}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                     material = lancer.material{color = 0.7, kr = kr}})
  s:add(lancer.sphere{center = {-1, 1, 0}, radius = 1,
                      material = lancer.material{color = {0.9, 0.3, 0.2}, ks = ks,
                                                 alpha = 30, absorb = "diffuse"}})
  s:add(lancer.sphere{center = {1.2, 0.7, -0.5}, radius = 0.7,
                      material = lancer.material{kd = mirrors and 0 or 0.6, ka = 0,
                                                 kr = mirrors and 0.9 or 0}})
  s:add(lancer.box{min = {0.2, 0, 1}, max = {1, 0.8, 1.8},
                   material = lancer.material{ka = 0, kd = 0.8}})
  s:add(lancer.sphere{center = {-2, 3, -1}, radius = 0.3,
                      material = lancer.material{kd = 0, emission = 20}})
  s:add(lancer.triangle{a = {-3, 0, 2}, b = {-1, 2, 2}, c = {-2.5, 1.5, 2.5}})
  s:add(lancer.point_light{position = {3, 5, -3}, intensity = 40})
  return s
end

T.test("S10 the planned shading equals the generic path, bit for bit", function()
  local scenes = {rich = rich_scene(true), diffuse = rich_scene(false),
                  plain = plane_scene()}
  scenes.plain:add(lancer.point_light{position = {0, 4, 0}, intensity = 10})
  for name, s in pairs(scenes) do
    for _, opts in ipairs{{samples = 4}, {samples = 1, cutoff = 0},
                          {samples = 1, specular = false}} do
      opts.width, opts.height = W, H
      local a = s:render(opts)
      opts.generic = true
      local b, st = s:render(opts)
      same(a, b, name .. " scene, generic path")
      T.eq(T.bad_pixels(b), 0, "NaN or infinite pixels")
      assert(st.effects.ambient, "the generic path runs everything")
    end
  end
end)

T.test("intersection tests are counted, the same whatever the thread count", function()
  local s = rich_scene(true)
  local _, a = s:render{width = W, height = H, threads = 1}
  local _, b = s:render{width = W, height = H, threads = 3}
  assert(a.prim_tests > 0 and a.node_tests > 0, "counted")
  T.eq(b.prim_tests, a.prim_tests, "primitive tests")
  T.eq(b.node_tests, a.node_tests, "node tests")
  assert(a.lua_seconds >= 0 and a.trace_seconds >= 0, "phases")
end)

T.test("explain: the ray tree of one pixel adds up to the pixel", function()
  local s = rich_scene(true)
  local img = s:render{width = W, height = H}
  for _, xy in ipairs{{5, 10}, {17, 8}, {12, 15}, {1, 1}} do
    local tree = s:explain{x = xy[1], y = xy[2], width = W, height = H}
    T.eq(tree.kind, "camera", "the root is the camera ray")
    local r, g, b = img:pixel(xy[1], xy[2])
    T.near(tree.contribution[1], r, 1e-5, "red total")
    T.near(tree.contribution[2], g, 1e-5, "green total")
    T.near(tree.contribution[3], b, 1e-5, "blue total")
    -- every shadow ray names its light and says whether it got through
    local function walk(node, depth)
      for _, child in ipairs(node.rays) do
        if child.kind == "shadow" or child.kind == "light" then
          assert(child.light and child.visible ~= nil, "shadow ray fields")
        else
          T.eq(child.kind, "reflection", "child kinds")
        end
        walk(child, depth + 1)
      end
    end
    walk(tree, 0)
  end
  -- the mirror sphere: the camera ray hits it, no shadow ray (kd = ks = 0),
  -- one reflection that adds everything the pixel shows
  local tree
  for x = 1, W do
    local t = s:explain{x = x, y = H // 2, width = W, height = H}
    if t.hit and t.hit.material == 3 then tree = t; break end
  end
  assert(tree, "some pixel of the middle row sees the mirror")
  T.eq(#tree.rays, 1, "only the reflection")
  T.eq(tree.rays[1].kind, "reflection", "kind")
  T.near(tree.rays[1].contribution[1], tree.contribution[1], 1e-6, "the mirror shows it")
  local text = tostring(tree)
  assert(text:find("camera hits sphere 2 (material 3)", 1, true), text)
  assert(text:find("\n  reflection ", 1, true), "indented: " .. text)
  T.check_error(function() s:explain{x = W + 1, y = 1, width = W, height = H} end,
                "test_effects.lua:", "'explain'", "field 'x'", "outside")
end)

T.test("--stats prints the ledger after each render", function()
  local path = os.tmpname() .. ".lua"
  local f = assert(io.open(path, "w"))
  f:write([[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 0, 0}}}
s:add(lancer.sphere{center = {0, 0, 0}, radius = 1})
s:add(lancer.point_light{position = {1, 3, -3}, intensity = 10})
s:render{width = 16, height = 16}
s:render{width = 8, height = 8, shadows = false}
]])
  f:close()
  local _, err, code = T.run(T.lancer .. " --stats " .. path)
  os.remove(path)
  T.eq(code, 0, "exit status: " .. err)
  assert(err:find("render 1: ", 1, true) and err:find("render 2: ", 1, true), err)
  assert(err:find("camera 256, shadow ", 1, true), err)
  assert(err:find("camera 64, shadow 0,", 1, true), err)
  assert(err:find("off reflect   no material in use has kr > 0", 1, true), err)
  assert(err:find("shadows off: no shadow rays", 1, true), err)
end)
