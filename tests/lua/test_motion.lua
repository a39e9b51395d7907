-- test_motion.lua: transforms, moved shapes, groups and instances, keyframes,
-- and listing and removing a scene's objects.
local T = require "harness"
local lancer = require "lancer"

local HERE = "test_motion.lua:"

local function scene()
  local s = lancer.scene{camera = lancer.camera{from = {0.5, 2, -7}, at = {0, 0, 0}, fov = 50},
                         ambient = 0.05}
  s:add(lancer.plane{point = {0, -1.5, 0}, normal = {0, 1, 0},
                     material = lancer.material{kr = 0.3}})
  s:add(lancer.point_light{position = {3, 5, -4}, intensity = 40})
  return s
end

local function same_image(a, b, what)
  local d = a:diff(b, 0)
  assert(d.max == 0, ("%s: images differ by %g at (%d, %d)"):format(what, d.max,
                                                                  d.worst_x, d.worst_y))
end

-- A closed octahedron of radius 1 at the origin.
local function octahedron(material)
  return lancer.mesh{vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1},
                                 {0, 0, -1}},
                     faces = {{1, 3, 5}, {3, 2, 5}, {2, 4, 5}, {4, 1, 5}, {3, 1, 6},
                              {2, 3, 6}, {4, 2, 6}, {1, 4, 6}},
                     material = material}
end

T.test("transforms compose right to left, apply, invert and print back", function()
  local T1 = lancer.translate(1, 2, 3) * lancer.rotate("y", 90) * lancer.scale(2)
  local p = T1:apply{1, 0, 0}               -- scaled to 2, turned to -z, moved
  assert(p[1] == 1 and p[2] == 2 and p[3] == 1, "x goes to -z, exactly")
  local v = T1:apply_vector{1, 0, 0}
  assert(v[1] == 0 and v[2] == 0 and v[3] == -2)
  local back = T1:inverse():apply(p)
  T.near(back[1], 1, 1e-15, "x back")
  assert(back[2] == 0 and back[3] == 0)
  assert(load("local lancer = ... return " .. tostring(T1))(lancer) == T1,
         "tostring builds it back")
  assert(lancer.rotate({0, 0, 1}, 90) == lancer.rotate("z", 90))
  assert(lancer.transform():is_identity())
  assert(lancer.scale(2, 3, 4):apply{1, 1, 1}[3] == 4)
  assert(lancer.translate{1, 2, 3}:apply{0, 0, 0}[2] == 2)
end)

T.test("singular and NaN transforms are refused naming the transform", function()
  T.check_error(function() return lancer.scale(0) end,
                HERE, "'scale'", "transform is singular")
  T.check_error(function() return lancer.scale(1, 0, 1) end, HERE, "transform is singular")
  T.check_error(function() return lancer.transform{{1, 2, 0, 0}, {2, 4, 0, 0}, {0, 0, 1, 0}} end,
                HERE, "'transform'", "transform is singular")
  T.check_error(function() return lancer.transform{{0 / 0, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}} end,
                HERE, "transform entry (1, 1) must be finite")
  T.check_error(function() return lancer.translate(0 / 0, 0, 0) end, HERE, "'translate'",
                "must be finite")
  T.check_error(function() return lancer.rotate({0, 0, 0}, 30) end, HERE, "'rotate'",
                "must have a direction")
  T.check_error(function() return lancer.rotate("w", 30) end, HERE, "axis 'x', 'y', 'z'")
  local ball = lancer.sphere{center = {0, 0, 0}, radius = 1}
  T.eq(ball:moved(lancer.scale(1, 2, 1)).kind, "ellipsoid", "a stretched sphere")
  T.check_error(function() return ball:moved({}) end, HERE, "lancer.Transform expected")
  -- in a group, a member that cannot be moved is refused when added, and
  -- nothing is added
  local s = scene()
  local g = lancer.group{lancer.sphere{center = {3, 0, 0}, radius = 1},
                         lancer.sphere{center = {0, 0, 0}, radius = 1e-29}}
  T.check_error(function() s:add(g:moved(lancer.scale(1e-3))) end,
                HERE, "'add'", "coordinate range")
  T.eq(#s:objects(), 2, "objects after the failed add")
end)

T.test("a moved sphere draws the bits of the sphere defined there", function()
  local m = lancer.material{color = {0.9, 0.3, 0.2}, ks = 0.5}
  local a, b = scene(), scene()
  local ball = lancer.sphere{center = {0.25, 0.5, 0}, radius = 0.5, material = m}
  a:add(ball:moved(lancer.translate(0.5, 0.25, -1) * lancer.rotate("x", 180) * lancer.scale(2)))
  b:add(lancer.sphere{center = {1, -0.75, -1}, radius = 1, material = m})
  same_image(a:render{width = 48, height = 36}, b:render{width = 48, height = 36},
             "moved sphere")
end)

T.test("a box under a quarter turn is the box built with turned edges", function()
  local box = lancer.box{corner = {1, 0, 2}, u = {2, 0, 0}, v = {0, 1, 0}, w = {0, 0, 3}}
  local moved = box:moved(lancer.rotate("y", 90))
  local c, u, w = moved.corner, moved.u, moved.w
  assert(c[1] == 2 and c[2] == 0 and c[3] == -1)
  assert(u[1] == 0 and u[3] == -2 and w[1] == 3 and w[3] == 0)
  local a, b = scene(), scene()
  a:add(moved)
  b:add(lancer.box{corner = {2, 0, -1}, u = {0, 0, -2}, v = {0, 1, 0}, w = {3, 0, 0}})
  same_image(a:render{width = 48, height = 36}, b:render{width = 48, height = 36}, "box")
end)

T.test("a mesh placed twice is stored once and draws like two moved copies", function()
  local mat = lancer.material{color = {0.4, 0.7, 0.9}, kr = 0.2}
  local oct = octahedron(mat)
  local t1 = lancer.translate(-1.3, 0, 0) * lancer.rotate({1, 1, 0}, 40)
  local t2 = lancer.translate(1.3, 0.2, 0.5) * lancer.scale(0.8, 1.2, 0.8)
  local a = scene()
  a:add(oct:moved(t1), oct:moved(t2))
  -- the copies: the same vertices moved in Lua
  local function copy(t)
    local vs = {}
    for i, v in ipairs{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}} do
      vs[i] = t:apply(v)
    end
    return lancer.mesh{vertices = vs, faces = {{1, 3, 5}, {3, 2, 5}, {2, 4, 5}, {4, 1, 5},
                       {3, 1, 6}, {2, 3, 6}, {4, 2, 6}, {1, 4, 6}}, material = mat}
  end
  local b = scene()
  b:add(copy(t1), copy(t2))
  local ia, sa = a:render{width = 64, height = 48}
  local ib, sb = b:render{width = 64, height = 48}
  T.eq(sa.primitives, 1 + 8, "plane + the octahedron's faces once")
  T.eq(sb.primitives, 1 + 16, "plane + two copies")
  T.eq(oct.vertex_count, 6, "vertices unchanged")
  T.eq(sa.self_hits, 0, "self-hits")
  local d = ia:diff(ib, 1 / 255)
  -- measured: 0 (the same triangles; asserted: within 1/255 everywhere)
  assert(d.within == 1 and d.max <= 1 / 255, ("differs by %g"):format(d.max))
end)

T.test("groups nest, compose and keep their members", function()
  local oct = octahedron()
  local lamp = lancer.group{lancer.sphere{center = {0, 1, 0}, radius = 0.2},
                            lancer.point_light{position = {0, 1.5, 0}, intensity = 3}}
  local rig = lancer.group{lamp, oct}
  T.eq(#rig, 2, "members")
  T.eq(tostring(rig), "lancer.Group (2 members)")
  local moved = rig:moved(lancer.translate(1, 0, 0)):moved(lancer.rotate("y", 90))
  T.eq(tostring(moved), "lancer.Group (2 members, moved)")
  local s = lancer.scene{}
  s:add(moved, rig)
  local objs = s:objects()
  T.eq(#objs, 6, "two of each member")
  -- translate, then turn: (0, 1, 0) + (1, 0, 0) turned about y is (0, 1, -1)
  local c = objs[1].object.center
  assert(c[1] == 0 and c[2] == 1 and c[3] == -1, "sphere centre")
  T.eq(objs[2].kind, "point_light")
  local p = objs[2].object.position
  assert(p[1] == 0 and p[2] == 1.5 and p[3] == -1, "light position")
  T.eq(objs[3].kind, "mesh")
  assert(objs[3].object == oct and objs[3].transform, "the mesh itself, moved")
  assert(objs[6].transform == nil, "added as it is: no transform")
  T.check_error(function() lancer.group{oct, 3} end, HERE, "element 2", "got number")
end)

T.test("instanced closed meshes at scales 1e-3, 1, 1e3 have no self-hits", function()
  for _, s in ipairs{1e-3, 1, 1e3} do
    local sc = lancer.scene{camera = lancer.camera{from = {0.3 * s, 2 * s, -7 * s},
                                                   at = {0, 0, 0}}}
    local oct = octahedron(lancer.material{kr = 0.8})
    for k = -1, 1 do
      sc:add(oct:moved(lancer.translate(2.2 * k * s, 0, 0) * lancer.rotate({1, 2, 3}, 25 * k)
                       * lancer.scale(s, s * (1 + 0.3 * (k + 1)), s)))
    end
    sc:add(lancer.point_light{position = {3 * s, 5 * s, -4 * s}, intensity = 40 * s * s})
    local img, st = sc:render{width = 64, height = 48}
    assert(st.rays.reflection > 100, "mirror rays traced")
    T.eq(st.self_hits, 0, "self-hits at scale " .. s)
    T.eq(T.bad_pixels(img), 0, "NaN or infinite pixels")
  end
end)

T.test("scene:objects() lists what was added, in order, with ids", function()
  local s = lancer.scene{}
  local red = lancer.material{color = {1, 0, 0}}
  local ball = lancer.sphere{center = {0, 1, 0}, radius = 1, material = red}
  local oct = octahedron()
  s:add(ball, lancer.point_light{position = {0, 5, 0}}, oct:moved(lancer.translate(0, 0, 3)))
  local objs = s:objects()
  T.eq(#objs, 3)
  T.eq(objs[1].id, 1) T.eq(objs[2].id, 2) T.eq(objs[3].id, 3)
  T.eq(objs[1].kind, "sphere")
  assert(objs[1].material == red, "the material itself")
  T.eq(objs[1].object.radius, 1)
  T.eq(objs[2].kind, "point_light")
  assert(objs[2].material == nil)
  T.eq(tostring(objs[1]), "#1 lancer.sphere{center = {0, 1, 0}, radius = 1}, material " ..
       tostring(red))
  assert(tostring(objs[3]):find("^#3 lancer.Mesh %(6 vertices, 8 faces%) moved by " ..
                                "lancer.transform{"), tostring(objs[3]))
end)

T.test("scene:remove(x) draws what the scene built without x draws", function()
  local oct = octahedron(lancer.material{color = {0.3, 0.8, 0.3}})
  local glow = lancer.material{emission = 3}
  local things = {
    lancer.sphere{center = {-1, 0, 0}, radius = 0.5},
    oct:moved(lancer.translate(0, 1, 0) * lancer.rotate("z", 30)),
    lancer.sphere{center = {0, 2.5, 0}, radius = 0.2, material = glow},
    lancer.box{min = {1, -1, 1}, max = {1.5, -0.5, 1.5}},
    lancer.point_light{position = {-3, 4, -4}, intensity = 20},
  }
  for drop = 1, #things do
    local a, b = scene(), scene()
    a:add(things)
    for i, x in ipairs(things) do if i ~= drop then b:add(x) end end
    a:render{width = 8, height = 6}                 -- compiled with everything first
    local victim = a:objects()[2 + drop]
    a:remove(victim)
    local ia, sa = a:render{width = 48, height = 36}
    local ib, sb = b:render{width = 48, height = 36}
    same_image(ia, ib, "without thing " .. drop)
    T.eq(sa.primitives, sb.primitives, "primitives")
    T.eq(sa.rays.shadow, sb.rays.shadow, "shadow rays")
    T.check_error(function() a:remove(victim) end, HERE, "'remove'",
                  ("no object %d in this scene (it was removed)"):format(victim.id))
  end
  local s = scene()
  local ball = lancer.sphere{center = {0, 0, 0}, radius = 1}
  s:add(ball, ball)
  T.check_error(function() s:remove(ball) end, HERE, "was added 2 times (ids 3, 4)")
  s:remove(3)
  s:remove(ball)                                   -- now only one: found by value
  T.eq(#s:objects(), 2, "plane and light left")
  T.check_error(function() s:remove(ball) end, HERE, "is not in this scene")
  T.check_error(function() s:remove(99) end, HERE, "no object 99 in this scene (never added)")
  T.check_error(function() s:remove("x") end, HERE, "id, entry of scene:objects()")
end)

-- The scene stores a plane's normal made unit; remove(shape) compares the
-- shape as the scene stores it, field by field, for every kind.
T.test("scene:remove(shape) finds each kind by value, a plane by its stored normal", function()
  local shapes = {
    lancer.plane{point = {0, -1, 0}, normal = {0, 3, 0}},
    lancer.plane{point = {0, 0, 4}, normal = {1, 2, 3}},
    lancer.quad{corner = {0, 0, 0}, u = {1, 0, 0}, v = {0, 1, 0}},
    lancer.box{corner = {0, 0, 0}, u = {1, 0, 0}, v = {0, 2, 0}, w = {0, 0, 3}},
    lancer.box{min = {2, 0, 0}, max = {3, 1, 1}},
    lancer.sphere{center = {1, 2, 3}, radius = 0.5},
  }
  local s = lancer.scene{}
  s:add(shapes)
  local kinds = {}
  for i, o in ipairs(s:objects()) do kinds[i] = o.kind end
  T.eq(table.concat(kinds, " "), "plane plane quad box box sphere", "kinds listed")
  T.eq(tostring(s:objects()[2].object), "lancer.plane{point = {0, 0, 4}, normal = " ..
       "{0.267261, 0.534522, 0.801784}}", "the plane as stored")
  for i = #shapes, 1, -1 do
    s:remove(shapes[i])
    T.eq(#s:objects(), i - 1, "objects after removing shape " .. i)
  end
  s:add(lancer.sphere{center = {1, 2, 3}, radius = 0.5})
  T.check_error(function() s:remove(lancer.sphere{center = {1, 2, 3}, radius = 0.25}) end,
                HERE, "'remove'", "radius = 0.25} is not in this scene")
end)

-- ---- interpolation ----------------------------------------------------------------

T.test("lerp and smoothstep: exact ends, closed-form midpoints", function()
  T.eq(lancer.lerp(2, 10, 0), 2) T.eq(lancer.lerp(2, 10, 1), 10)
  T.eq(lancer.lerp(2, 10, 0.5), 6) T.eq(lancer.lerp(2, 10, 0.25), 4)
  local v = lancer.lerp({0, 1, 2}, {4, 5, 6}, 0.5)
  assert(v[1] == 2 and v[2] == 3 and v[3] == 4)
  T.eq(lancer.smoothstep(0.5), 0.5)
  T.eq(lancer.smoothstep(0.25), 0.15625, "3/16 - 2/64")
  T.eq(lancer.smoothstep(2, 4, 3), 0.5)
  T.eq(lancer.smoothstep(2, 4, 1), 0) T.eq(lancer.smoothstep(2, 4, 5), 1)
  T.eq(lancer.lerp_angle(350, 10, 0.5), 360, "the short way round")
  T.eq(lancer.lerp_angle(10, 350, 0.25), 5)
  T.check_error(function() lancer.lerp(1, {2}, 0.5) end, HERE, "'lerp'")
end)

T.test("easing curves run from 0 to 1 and never go back", function()
  for name, f in pairs(lancer.ease) do
    T.eq(f(0), 0, name .. "(0)")
    T.near(f(1), 1, 1e-15, name .. "(1)")
    local prev = 0
    for i = 1, 1000 do
      local y = f(i / 1000)
      assert(y >= prev, ("%s decreases at %g"):format(name, i / 1000))
      prev = y
    end
  end
  T.eq(lancer.ease.in_out_cubic(0.5), 0.5)
  T.eq(lancer.ease.in_quad(0.5), 0.25)
  T.eq(lancer.ease.out_quad(0.5), 0.75)
end)

T.test("keyframes: exact at the keys, eased between, held outside", function()
  local f = lancer.keyframes{{0, {0, 0, 0}}, {1, {2, 4, 6}}, {3, {2, 0, 6}, "ease_in_out"}}
  local function is(v, x, y, z) return v[1] == x and v[2] == y and v[3] == z end
  assert(is(f(-1), 0, 0, 0) and is(f(0), 0, 0, 0) and is(f(1), 2, 4, 6) and is(f(3), 2, 0, 6))
  assert(is(f(5), 2, 0, 6))
  assert(is(f(0.5), 1, 2, 3), "linear midpoint")
  assert(is(f(2), 2, 2, 6), "ease_in_out midpoint: half way")
  assert(f(1.5)[2] > 3, "ease_in leaves slowly") -- in_out_cubic(0.25) = 1/16: 4 - 4/16
  T.eq(f(1.5)[2], 4 - 4 * 0.0625)
  local g = lancer.keyframes{{0, 0}, {2, 10, "smoothstep"}}
  T.eq(g(1), 5) T.eq(g(0.5), 10 * 0.15625)
  T.check_error(function() lancer.keyframes{{0, 1}, {0, 2}} end, HERE, "times must increase")
  T.check_error(function() lancer.keyframes{{0, 1}, {1, 2, "bounce"}} end, HERE,
                "unknown easing 'bounce'")
end)

T.test("two placements of one open mesh facing each other: mirror rays between them are no self-hits", function()
  -- The same face of two placements shares its triangle id; a hit tells
  -- them apart by the placement, so the self-hit counter stays 0.
  local square = lancer.mesh{vertices = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}},
                             faces = {{1, 2, 3}, {1, 3, 4}},
                             material = lancer.material{kd = 0.2, kr = 0.8}}
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, -0.5}, at = {0.2, 0.1, 1}, fov = 60},
                         background = 0.5, max_depth = 6}
  s:add(square:moved(lancer.translate(0, 0, 1)))
  s:add(square:moved(lancer.translate(0, 0, -1) * lancer.rotate("y", 180)))
  local img, st = s:render{width = 16, height = 12, cutoff = 0}
  assert(st.rays.reflection > 16 * 12, "rays bounce between the two")
  T.eq(st.self_hits, 0, "self-hits")
  T.eq(T.bad_pixels(img), 0, "NaN or infinite channels")
end)
