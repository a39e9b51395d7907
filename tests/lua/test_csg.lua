-- test_csg.lua: CSG objects in scenes: coincident and tangent cutters that
-- leave every pixel of the plain box, a camera inside a CSG cavity (H3's
-- closed form), union against merge, moved and instanced objects, a mesh
-- leaf against the box, scale and translation invariance with CSG, no
-- self-hit, the price in the ledger, listing, removing, explain's names,
-- and every refusal naming the operand.
local T = require "harness"
local lancer = require "lancer"

local HERE = "test_csg.lua:"

local function no_bad(img, what)
  T.eq(T.bad_pixels(img), 0, what .. ": NaN or infinite channels")
end

-- Every pixel of a and b equal, bit for bit.
local function identical(a, b, what)
  for y = 1, a.height do
    for x = 1, a.width do
      local r1, g1, b1 = a:pixel(x, y)
      local r2, g2, b2 = b:pixel(x, y)
      if r1 ~= r2 or g1 ~= g2 or b1 ~= b2 then
        error(("%s: pixel (%d, %d) is (%g, %g, %g), the plain box's (%g, %g, %g)"):format(
          what, x, y, r1, g1, b1, r2, g2, b2), 2)
      end
    end
  end
end

local RED = lancer.material{color = {0.9, 0.3, 0.2}, ks = 0.3, alpha = 20}
local BLUE = lancer.material{color = {0.2, 0.4, 0.9}}
local GREEN = lancer.material{color = {0.3, 0.9, 0.3}}
local MIRROR = lancer.material{color = {0.9, 0.9, 0.9}, kd = 0.2, kr = 0.7}

-- A lit scene around `thing` (a plane under it, one light), camera at eye.
local function stage(thing, eye, at)
  local s = lancer.scene{camera = lancer.camera{from = eye, at = at or {0.5, 0.5, 0.5},
                                                fov = 40},
                         ambient = 0.05, background = {0.1, 0.15, 0.3}}
  s:add(lancer.plane{point = {0, -0.5, 0}, normal = {0, 1, 0}})
  s:add(lancer.point_light{position = {3, 5, -3}, intensity = 40})
  s:add(thing)
  return s
end

local OPTS = {width = 96, height = 72, samples = 4, seed = 2}

T.test("a cutter flush with a face, beside it or tangent to it leaves the plain box's pixels",
       function()
  local cases = {
    {"flush on top", lancer.box{min = {0.25, 0.25, 1}, max = {0.75, 0.75, 2}}},
    {"flush beside", lancer.box{min = {1, -0.5, 0.2}, max = {3, 0.5, 0.8}}},
    {"tangent sphere", lancer.sphere{center = {0.5, 0.5, 1.5}, radius = 0.5}},
    {"sphere along an edge", lancer.sphere{center = {1.5, 0.5, 1.5}, radius = math.sqrt(0.5)}},
  }
  local rot = lancer.translate(0.5, 0.2, 0) * lancer.rotate({1, 2, 3}, 37)
  for _, moved in ipairs{false, true} do
    local box = lancer.box{min = {0, 0, 0}, max = {1, 1, 1}, material = RED}
    local eyes = {{2.5, 3, -3}, {3, 1.5, 0.4}, {0.5, 4, 0.2}}
    for _, c in ipairs(cases) do
      local cut = lancer.difference{box, c[2]:moved(lancer.transform()), material = BLUE}
      local a, b = cut, box
      if moved then a, b = cut:moved(rot), box:moved(rot) end
      for i, eye in ipairs(eyes) do
        local want = stage(b, eye):render(OPTS)
        local got, st = stage(a, eye):render(OPTS)
        no_bad(got, c[1])
        T.eq(st.self_hits, 0, c[1] .. ": self-hits")
        identical(got, want, ("%s%s, eye %d"):format(c[1], moved and ", rotated" or "", i))
      end
    end
  end
end)

T.test("a pocket flush with the top face shows its floor in the cutter's material", function()
  local box = lancer.box{min = {0, 0, 0}, max = {1, 1, 1}, material = RED}
  local pocket = lancer.box{min = {0.25, 0.5, 0.25}, max = {0.75, 1, 0.75}, material = BLUE}
  for _, cut in ipairs{"cutter", "object"} do
    local s = stage(lancer.difference{box, pocket, cut = cut}, {0.5, 4, 0.51},
                    {0.5, 0.5, 0.5})
    local tree = s:explain{x = 48, y = 36, width = 96, height = 72}
    T.near(tree.hit.point[2], 0.5, 0, "the pocket's floor")
    T.eq(tree.hit.normal[2], 1, "its normal, up out of the box")
    T.eq(tree.hit.material, cut == "cutter" and 3 or 2, "its material")
    T.eq(tree.hit.shape, "box (node 3 of CSG object 1)", "explain's name")
  end
end)

T.test("camera and light inside a CSG cavity: uniform kd*I/R^2 (H3 through a difference)",
       function()
  local kd, C, want = 0.8, {1, 0.5, 0.25}, 0.6
  for _, case in ipairs{{1, 0}, {1e-3, 1e4}, {1e3, 1e7}} do
    local R, shift = case[1], case[2]
    local c = {shift, shift / 2, shift / 3}
    local wall = lancer.material{kd = kd, color = C}
    local shell = lancer.difference{
      lancer.box{min = {c[1] - 2 * R, c[2] - 2 * R, c[3] - 2 * R},
                 max = {c[1] + 2 * R, c[2] + 2 * R, c[3] + 2 * R}, material = RED},
      lancer.sphere{center = c, radius = R, material = wall}}
    local s = lancer.scene{camera = lancer.camera{
      from = {c[1] + 0.3 * R, c[2] + 0.2 * R, c[3] - 0.4 * R},
      at = {c[1] + 0.3 * R, c[2], c[3] + R}, fov = 100}}
    s:add(shell, lancer.point_light{position = c, intensity = want * R * R / kd})
    local img, st = s:render{width = 32, height = 24}
    no_bad(img, "cavity")
    local what = ("R %g at %g"):format(R, shift)
    for y = 1, img.height do
      for x = 1, img.width do
        local r, g, b = img:pixel(x, y)
        -- the light at the centre meets the wall head-on: cos = 1
        assert(math.abs(r - want * C[1]) <= 1 / 255 and math.abs(g - want * C[2]) <= 1 / 255
               and math.abs(b - want * C[3]) <= 1 / 255,
               ("%s: pixel (%d, %d) is (%g, %g, %g)"):format(what, x, y, r, g, b))
      end
    end
    assert(st.csg_tests > 0, "the sweep ran")
  end
end)

T.test("a top-level union draws every operand's surfaces; merge only the boundary", function()
  local a = lancer.sphere{center = {-0.4, 0, 0}, radius = 1, material = RED}
  local b = lancer.sphere{center = {0.4, 0, 0}, radius = 1, material = BLUE}
  local function first(thing, from, dir)
    local s = lancer.scene{camera = lancer.camera{from = from,
      at = {from[1] + dir[1], from[2] + dir[2], from[3] + dir[3]}, fov = 1}}
    s:add(thing)
    return s:explain{x = 1, y = 1, width = 1, height = 1}.hit
  end
  -- from inside both, looking along +x: the union shows a's far side at
  -- x = 0.6, merge only b's at 1.4
  local u = first(lancer.union{a, b}, {0, 0, 0}, {1, 0, 0})
  local m = first(lancer.merge{a, b}, {0, 0, 0}, {1, 0, 0})
  T.near(u.distance, 0.6, 1e-12, "union: a's inner surface")
  T.near(m.distance, 1.4, 1e-12, "merge: the boundary")
  T.eq(u.shape, "sphere (node 2 of CSG object 1)", "union's leaf")
  T.eq(m.shape, "sphere (node 3 of CSG object 1)", "merge's leaf")
  -- from outside, both show the first boundary
  local u2 = first(lancer.union{a, b}, {-5, 0, 0}, {1, 0, 0})
  local m2 = first(lancer.merge{a, b}, {-5, 0, 0}, {1, 0, 0})
  T.near(u2.distance, 3.6, 1e-12, "union from outside")
  T.near(m2.distance, 3.6, 1e-12, "merge from outside")
  -- inside another operation a union is a set: no inner surface
  local n = first(lancer.intersection{lancer.union{a, b}, lancer.sphere{
    center = {0, 0, 0}, radius = 3}}, {0, 0, 0}, {1, 0, 0})
  T.near(n.distance, 1.4, 1e-12, "a nested union")
end)

-- The classic: (box & sphere) - three cylinders, with a mirror sphere.
local function classic(P, V, s)
  local function cyl(a)
    return lancer.cylinder{base = P{0.5 - a[1], 0.5 - a[2], 0.5 - a[3]},
                           axis = V{2 * a[1], 2 * a[2], 2 * a[3]}, radius = 0.28 * s,
                           material = GREEN}
  end
  return lancer.difference{
    lancer.intersection{lancer.box{min = P{0, 0, 0}, max = P{1, 1, 1}, material = RED},
                        lancer.sphere{center = P{0.5, 0.5, 0.5}, radius = 0.68 * s,
                                      material = MIRROR}},
    cyl{1, 0, 0}, cyl{0, 1, 0}, cyl{0, 0, 1}}
end

-- CSG of every kind of leaf, mirrors included, at scale s moved by (T, T/2, T/3).
local function csg_scene(s, T)
  local function P(p) return {p[1] * s + T, p[2] * s + T / 2, p[3] * s + T / 3} end
  local function V(v) return {v[1] * s, v[2] * s, v[3] * s} end
  local sc = lancer.scene{camera = lancer.camera{from = P{0.3, 2.4, -4.5}, at = P{0.4, 0.4, 0},
                                                 fov = 55},
                          ambient = 0.05, background = {0.1, 0.15, 0.3}}
  sc:add(lancer.plane{point = P{0, 0, 0}, normal = {0, 1, 0},
                      material = lancer.material{color = {0.8, 0.8, 0.7}}})
  sc:add(classic(P, V, s))
  sc:add(lancer.intersection{
    lancer.torus{center = P{-1.5, 0.35, 0.2}, axis = {0.2, 1, -0.3}, major = 0.7 * s,
                 minor = 0.3 * s, material = BLUE},
    lancer.box{min = P{-2.4, 0, -0.6}, max = P{-1.3, 0.8, 1}, material = MIRROR}})
  sc:add(lancer.merge{
    lancer.cone{base = P{2, 0, 0}, top = P{2, 0.6, 0}, base_radius = 0.5 * s,
                top_radius = 0.3 * s, material = RED},
    lancer.cone{base = P{2, 0.6, 0}, top = P{2, 1.2, 0}, base_radius = 0.3 * s,
                top_radius = 0.1 * s, material = RED},
    lancer.ellipsoid{center = P{2, 1.3, 0}, radii = V{0.25, 0.15, 0.25}, material = GREEN}})
  local cube = lancer.mesh{vertices = {{-1, -1, -1}, {1, -1, -1}, {-1, 1, -1}, {1, 1, -1},
                                       {-1, -1, 1}, {1, -1, 1}, {-1, 1, 1}, {1, 1, 1}},
                           faces = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5}, {3, 7, 8, 4},
                                    {1, 5, 7, 3}, {2, 4, 8, 6}}, material = BLUE}
  sc:add(lancer.difference{
    cube:moved(lancer.translate(P{0.2, 0.3, -1.6}) * lancer.scale(0.3 * s)),
    lancer.sphere{center = P{0.35, 0.6, -1.8}, radius = 0.3 * s, material = MIRROR}})
  sc:add(lancer.point_light{position = P{3, 5, -4}, intensity = 30 * s * s})
  return sc
end

local INV = {width = 64, height = 48, samples = 16, seed = 5}
local ref_image, ref_stats

local function reference()
  if not ref_image then
    ref_image, ref_stats = csg_scene(1, 0):render(INV)
    no_bad(ref_image, "scale 1")
  end
  return ref_image
end

local function invariance(img, st, what)
  no_bad(img, what)
  T.eq(st.self_hits, 0, what .. ": self-hits")
  local d = img:diff(reference(), 1 / 255)
  assert(d.within >= 0.999, ("%s: only %.3f%% of pixels within 1/255 (worst %g at %d, %d)")
         :format(what, 100 * d.within, d.max, d.worst_x, d.worst_y))
end

T.test("H1 with CSG: scale 1e-4..1e6, >= 99.9% within 1/255, no self-hit", function()
  reference()
  T.eq(ref_stats.self_hits, 0, "self-hits at scale 1")
  assert(ref_stats.rays.reflection > 0 and ref_stats.csg_tests > 0, "mirrors and sweeps")
  for _, s in ipairs{1e-4, 1e-2, 1e2, 1e4, 1e6} do
    local img, st = csg_scene(s, 0):render(INV)
    invariance(img, st, ("scale %g"):format(s))
  end
end)

T.test("H2 with CSG: moved 1e3..1e7, and copies by scene:transformed", function()
  for _, shift in ipairs{1e3, 1e5, 1e7} do
    local img, st = csg_scene(1, shift):render(INV)
    invariance(img, st, ("moved %g"):format(shift))
  end
  local base = csg_scene(1, 0)
  for _, v in ipairs{{1e-4, {0, 0, 0}}, {1e6, {0, 0, 0}}, {1, {1e7, 5e6, 1e7 / 3}}} do
    local img, st = base:transformed(v[1], v[2]):render(INV)
    invariance(img, st, ("transformed %g, %g"):format(v[1], v[2][1]))
  end
end)

T.test("lancer --check finds the CSG example stable", function()
  local out, err, code = T.run(T.quote(T.lancer) .. " --check examples/11_csg.lua")
  T.eq(code, 0, "exit status: " .. err)
  assert(err:find("check: 0 of %d+ renders unstable"), err)
end)

T.test("a moved CSG object is its leaves moved; instances are listed and removed one by one",
       function()
  local P = function(p) return p end
  local obj = classic(P, P, 1)
  local m = lancer.translate(0.2, 0.1, 0.3) * lancer.rotate({0, 1, 0.2}, 25) * lancer.scale(1.2)
  local cyl = function(a)
    return lancer.cylinder{base = {0.5 - a[1], 0.5 - a[2], 0.5 - a[3]},
                           axis = {2 * a[1], 2 * a[2], 2 * a[3]}, radius = 0.28,
                           material = GREEN}:moved(m)
  end
  local by_leaf = lancer.difference{
    lancer.intersection{lancer.box{min = {0, 0, 0}, max = {1, 1, 1}, material = RED}:moved(m),
                        lancer.sphere{center = {0.5, 0.5, 0.5}, radius = 0.68,
                                      material = MIRROR}:moved(m)},
    cyl{1, 0, 0}, cyl{0, 1, 0}, cyl{0, 0, 1}}
  local eye = {2, 2.5, -3}
  identical(stage(obj:moved(m), eye):render(OPTS), stage(by_leaf, eye):render(OPTS),
            "moved whole against moved leaf by leaf")
  -- one object, three placings
  local s = stage(lancer.group{obj:moved(lancer.translate(-1.5, 0, 0)), obj,
                               obj:moved(lancer.translate(1.5, 0, 0))}, {0.5, 3, -5})
  local img = s:render(OPTS)
  no_bad(img, "instances")
  local list = s:objects()
  T.eq(#list, 5, "plane, light, three CSG objects")
  T.eq(list[3].kind, "difference", "a CSG object's kind")
  assert(tostring(list[4].object):find("^lancer.difference{lancer.intersection{lancer.box{"),
         tostring(list[4].object))
  T.eq(tostring(list[4]), "#4 " .. tostring(list[4].object), "the entry prints its object")
  s:remove(list[4].id)
  T.eq(#s:objects(), 4, "one placing removed")
  -- added as itself, it is removed by value
  local t = stage(obj, eye)
  t:remove(obj)
  T.eq(#t:objects(), 2, "removed by value")
  t:add(obj, obj)
  T.check_error(function() t:remove(obj) end, HERE, "added 2 times", "remove one by id")
end)

T.test("scene:objects() gives back a CSG object that renders the same", function()
  local cube = lancer.mesh{vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1},
                                       {1, 0, 1}, {0, 1, 1}, {1, 1, 1}},
                           faces = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5}, {3, 7, 8, 4},
                                    {1, 5, 7, 3}, {2, 4, 8, 6}}}
  local obj = lancer.difference{
    cube:moved(lancer.rotate("y", 10)),
    lancer.union{lancer.sphere{center = {1, 1, 0}, radius = 0.6},
                 lancer.cylinder{base = {0.5, -1, 0.5}, axis = {0, 3, 0}, radius = 0.2}},
    material = GREEN, cut = "object"}
  local eye = {2.5, 3, -3}
  local a = stage(obj, eye)
  local listed = a:objects()[3].object
  assert(tostring(listed):find("cut = 'object'", 1, true), tostring(listed))
  identical(stage(listed, eye):render(OPTS), a:render(OPTS), "listed and added again")
end)

T.test("a mesh cube minus a sphere draws as the box minus the sphere", function()
  local cube = lancer.mesh{vertices = {{-1, -1, -1}, {1, -1, -1}, {-1, 1, -1}, {1, 1, -1},
                                       {-1, -1, 1}, {1, -1, 1}, {-1, 1, 1}, {1, 1, 1}},
                           faces = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5}, {3, 7, 8, 4},
                                    {1, 5, 7, 3}, {2, 4, 8, 6}}, material = RED}
  local box = lancer.box{min = {-1, -1, -1}, max = {1, 1, 1}, material = RED}
  local ball = lancer.sphere{center = {0.7, 0.8, -0.9}, radius = 0.8, material = BLUE}
  for i, eye in ipairs{{3, 2.5, -4}, {-2, 3, -3}, {0.5, 0.6, -4}} do
    local a = stage(lancer.difference{cube, ball}, eye, {0, 0, 0}):render(OPTS)
    local b = stage(lancer.difference{box, ball}, eye, {0, 0, 0}):render(OPTS)
    no_bad(a, "mesh leaf")
    local d = a:diff(b, 1 / 255)
    T.eq(d.within, 1, ("eye %d: share of pixels within 1/255 (worst %g at %d, %d)"):format(
      i, d.max, d.worst_x, d.worst_y))
  end
end)

T.test("the price: csg_tests counts the sweeps, 0 without CSG; the ledger shows it", function()
  local plain = stage(lancer.box{min = {0, 0, 0}, max = {1, 1, 1}}, {2, 3, -3})
  local _, st = plain:render(OPTS)
  T.eq(st.csg_tests, 0, "no CSG, no sweep")
  assert(not lancer.ledger(st):find("csg"), "no csg line")
  local _, st2 = stage(classic(function(p) return p end, function(p) return p end, 1),
                       {2, 3, -3}):render(OPTS)
  assert(st2.csg_tests > st2.rays.camera, "several leaf tests per ray")
  assert(lancer.ledger(st2):find("csg       %d+ leaf tests in the interval sweeps"),
         lancer.ledger(st2))
end)

T.test("explain names the leaf hit, in the object's own numbering", function()
  local id = function(p) return p end
  local s = stage(classic(id, id, 1), {0.5, 2.5, -3}, {0.5, 0.5, 0.5})
  local seen = {}
  for y = 20, 52, 8 do
    for x = 30, 66, 6 do
      local hit = s:explain{x = x, y = y, width = 96, height = 72}.hit
      if hit and hit.shape:find("CSG") then
        assert(hit.shape:find("^%a+ %(node %d of CSG object 1%)$"), hit.shape)
        seen[hit.shape] = true
      end
    end
  end
  assert(seen["box (node 3 of CSG object 1)"] and
         seen["cylinder (node 6 of CSG object 1)"], "the box's face and a hole's wall")
end)

-- ---- refusals ---------------------------------------------------------------------
T.test("open operands are refused, naming the operand", function()
  local box = lancer.box{min = {0, 0, 0}, max = {1, 1, 1}}
  T.check_error(function() return lancer.difference{box, lancer.plane{point = {0, 0, 0},
    normal = {0, 1, 0}}} end, HERE, "bad argument #1 to 'difference'",
    "(operand 2: a plane is not a closed solid)")
  T.check_error(function() return lancer.union{lancer.quad{corner = {0, 0, 0},
    u = {1, 0, 0}, v = {0, 1, 0}}, box} end, HERE, "bad argument #1 to 'union'",
    "operand 1: a quad is not a closed solid")
  T.check_error(function() return lancer.intersection{box, lancer.disc{center = {0, 0, 0},
    normal = {0, 1, 0}, radius = 1}} end, HERE, "'intersection'",
    "operand 2: a disc is not a closed solid")
  T.check_error(function() return lancer.merge{box, lancer.cylinder{base = {0, 0, 0},
    axis = {0, 1, 0}, radius = 1, caps = false}} end, HERE, "'merge'",
    "operand 2: a cylinder without caps is not a closed solid")
  T.check_error(function() return lancer.merge{box, lancer.cone{base = {0, 0, 0},
    axis = {0, 1, 0}, base_radius = 1, top_radius = 0, caps = false}} end, HERE,
    "operand 2: a cone without caps is not a closed solid")
  T.check_error(function() return lancer.union{box, lancer.point_light{position = {0, 0, 0}}}
    end, HERE, "operand 2: a point light is not a closed solid")
  T.check_error(function() return lancer.union{box, lancer.group{box,
    lancer.point_light{position = {0, 0, 0}}}} end, HERE,
    "operand 2, member 2: a point light is not a closed solid")
  T.check_error(function() return lancer.union{box, 5} end, HERE,
    "operand 2: shape, mesh, group or CSG object expected, got number")
  T.check_error(function() return lancer.union{} end, HERE,
    "at least one operand expected, got none")
  T.check_error(function() return lancer.union(box) end, HERE, "table expected")
end)

T.test("an open mesh, or one whose windings disagree, is refused naming the edge", function()
  local v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}
  local open = lancer.mesh{vertices = v, faces = {{1, 3, 2}, {1, 2, 4}, {2, 3, 4}}}
  T.check_error(function() return lancer.difference{open, lancer.sphere{center = {0, 0, 0},
    radius = 1}} end, HERE, "operand 1 (lancer.Mesh (4 vertices, 3 faces)): the mesh is "
    .. "open: the edge between vertices 1 and 3 is in face 1 only (counting from 1)")
  local flipped = lancer.mesh{vertices = v, faces = {{1, 3, 2}, {1, 2, 4}, {2, 3, 4},
                                                     {1, 3, 4}}}
  T.check_error(function() return lancer.merge{flipped} end, HERE,
    "faces 1 and 4 both run the edge from vertex 1 to 3: their windings disagree")
  local closed = lancer.mesh{vertices = v, faces = {{1, 3, 2}, {1, 2, 4}, {2, 3, 4},
                                                    {1, 4, 3}}}
  local ok = lancer.merge{closed}
  -- a mesh that opens after the object was built is refused when added
  closed:add_vertices{{2, 2, 2}}
  closed:add_faces{{1, 2, 5}}
  T.check_error(function() lancer.scene{}:add(ok) end, HERE, "bad argument #1 to 'add'",
    "the mesh is not a closed surface: the edge between vertices 1 and 2 is in 3 faces")
end)

T.test("unknown fields, a bad cut and a bad material are refused naming the field", function()
  local box = lancer.box{min = {0, 0, 0}, max = {1, 1, 1}}
  T.check_error(function() return lancer.union{box, materal = RED} end, HERE,
    "unknown field 'materal'; did you mean 'material'?")
  T.check_error(function() return lancer.union{box, cut = "object"} end, HERE,
    "unknown field 'cut'")
  T.check_error(function() return lancer.difference{box, box, cut = "objet"} end, HERE,
    "field 'cut': expected one of 'cutter', 'object', got 'objet'")
  T.check_error(function() return lancer.difference{box, material = 3} end, HERE,
    "field 'material'", "lancer.Material expected")
  T.check_error(function() return lancer.union{box, [5] = box} end, HERE,
    "unexpected key [5]")
  T.check_error(function() return lancer.union{box}:moved(5) end, HERE,
    "lancer.Transform expected")
end)

T.test("CSG objects nest at most 200 deep", function()
  local box = lancer.box{min = {0, 0, 0}, max = {1, 1, 1}}
  local x = box
  for _ = 1, 200 do x = lancer.union{x} end
  T.check_error(function() return lancer.union{x} end, HERE,
    "CSG operations nest at most 200 deep, got 201")
end)

T.test("CSG hits through scene:intersect and uv textures: the leaf's own", function()
  -- A sphere cut by a box through its centre: the part of the sphere left
  -- is the sphere's own surface, with the sphere's texture coordinates.
  local ball = lancer.sphere{center = {0, 0, 0}, radius = 1}
  local cut = lancer.difference{ball, lancer.box{min = {-2, -2, -2}, max = {2, 2, -0.5}}}
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}}}
  local before = s:add(lancer.point_light{position = {0, 3, 5}})
  s:add(cut)
  local id = s:objects()[#s:objects()].id
  local h = s:intersect{origin = {0.3, 0.2, 5}, direction = {0, 0, -1}}
  local plain = lancer.scene{camera = s.camera}
  plain:add(ball)
  local p = plain:intersect{origin = {0.3, 0.2, 5}, direction = {0, 0, -1}}
  T.eq(h.id, id, "the CSG object's id")
  T.eq(h.kind, "sphere", "the leaf's kind")
  T.eq(h.t, p.t, "the sphere's distance")
  T.eq(h.uv[1], p.uv[1], "u of the sphere"); T.eq(h.uv[2], p.uv[2], "v of the sphere")
  -- An image over uv on the leaf: each pixel as on the plain sphere.
  local img = lancer.image{width = 4, height = 2}
  for y = 1, 2 do for x = 1, 4 do img:set(x, y, x / 4, y / 2, 0.5) end end
  local m = lancer.material{ka = 1, kd = 0, color = lancer.image_texture{image = img}}
  local function look(obj)
    local sc = lancer.scene{camera = lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}},
                            ambient = 1}
    sc:add(obj)
    return sc:render{width = 16, height = 16}
  end
  local a = look(lancer.difference{lancer.sphere{center = {0, 0, 0}, radius = 1, material = m},
                                   lancer.box{min = {-2, -2, -2}, max = {2, 2, -0.5}}})
  local b = look(lancer.sphere{center = {0, 0, 0}, radius = 1, material = m})
  T.eq(a:diff(b, 0).max, 0, "the cut sphere's front as the sphere's")
  -- A pattern in object space on a moved leaf: as on the moved shape alone.
  local st = lancer.material{ka = 1, kd = 0, color = lancer.stripes{a = {1, 0, 0},
                             b = {0, 0, 1}, scale = 0.3, mapping = "object"}}
  local move = lancer.translate(0.45, 0.1, 0) * lancer.rotate({0, 0, 1}, 30)
  local cyl = lancer.cylinder{base = {0, -0.8, 0}, top = {0, 0.8, 0}, radius = 0.6,
                              material = st}:moved(move)
  local c = look(lancer.difference{cyl, lancer.box{min = {5, 5, 5}, max = {6, 6, 6}}})
  T.eq(c:diff(look(cyl), 0).max, 0, "object space: the moved leaf's own")
  assert(before, "a light id")
end)
