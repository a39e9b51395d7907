-- test_mesh.lua: triangles, meshes (nested and flat arrays), OBJ files.
local T = require "harness"
local lancer = require "lancer"

local HERE = "test_mesh.lua:"

-- A camera looking straight down at the origin from height 4, a light at
-- the camera: a horizontal white surface at y = 0 reads I/16 head-on.
local function top_scene()
  local s = lancer.scene{camera = lancer.camera{from = {0, 4, 0}, at = {0, 0, 0},
                                                up = {0, 0, 1}, fov = 40}}
  s:add(lancer.point_light{position = {0, 4, 0}, intensity = 16})
  return s
end

local function same_image(a, b, what)
  local d = a:diff(b, 0)
  assert(d.max == 0, ("%s: images differ by %g at (%d, %d)"):format(what, d.max,
                                                                  d.worst_x, d.worst_y))
end

-- A 2x2 square at y = 0 as two triangles.
local SQUARE_V = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}}
local SQUARE_F = {{1, 2, 3}, {1, 3, 4}}

T.test("a triangle reads the diffuse closed form at its centre", function()
  local s = top_scene()
  s:add(lancer.triangle{a = {-3, 0, -3}, b = {3, 0, -3}, c = {0, 0, 3}})
  local img, st = s:render{width = 9, height = 9}
  T.near(select(1, img:pixel(5, 5)), 1.0, 1e-6, "I/h^2 = 16/16")
  T.eq(st.primitives, 1, "one triangle")
end)

T.test("nested and flat arrays build the same mesh", function()
  local nested = lancer.mesh{vertices = SQUARE_V, faces = SQUARE_F}
  local flat = lancer.mesh{vertices = {-1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1},
                           faces = {1, 2, 3, 1, 3, 4}}
  T.eq(nested.vertex_count, 4, "vertices")
  T.eq(flat.face_count, 2, "faces")
  local a, b = top_scene(), top_scene()
  a:add(nested)
  b:add(flat)
  same_image(a:render{width = 16, height = 16}, b:render{width = 16, height = 16}, "flat")
end)

T.test("a polygon face becomes a fan of triangles", function()
  local m = lancer.mesh{vertices = SQUARE_V, faces = {{1, 2, 3, 4}}}
  T.eq(m.face_count, 2, "a quad is two triangles")
  local a, b = top_scene(), top_scene()
  a:add(m)
  b:add(lancer.mesh{vertices = SQUARE_V, faces = SQUARE_F})
  same_image(a:render{width = 16, height = 16}, b:render{width = 16, height = 16}, "fan")
end)

T.test("meshes grow by add_vertices and add_faces", function()
  local m = lancer.mesh{}
  T.eq(m:add_vertices{-1, 0, -1, 1, 0, -1}, 2, "vertex count returned")
  m:add_vertices{{1, 0, 1}, {-1, 0, 1}}
  T.eq(m:add_faces{1, 2, 3}, 1, "face count returned")
  m:add_faces{{1, 3, 4}}
  local a, b = top_scene(), top_scene()
  a:add(m)
  b:add(lancer.mesh{vertices = SQUARE_V, faces = SQUARE_F})
  same_image(a:render{width = 16, height = 16}, b:render{width = 16, height = 16}, "grown")
end)

T.test("degenerate triangles are skipped: same image, counted, no NaN", function()
  local v = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, {0, 0, 0}, {0, 0, 0},
             {2, 0, 2}, {0, 1e-300, 0}}
  local clean = lancer.mesh{vertices = v, faces = SQUARE_F}
  local dirty = lancer.mesh{vertices = v, faces = {{1, 2, 3}, {5, 5, 5}, {1, 3, 4},
                                                   {5, 6, 1}, {1, 3, 7}, {5, 8, 6}}}
  local a, b = top_scene(), top_scene()
  a:add(clean)
  b:add(dirty)
  local ia = a:render{width = 16, height = 16}
  local ib, st = b:render{width = 16, height = 16}
  same_image(ia, ib, "degenerate")
  T.eq(st.degenerate, 4, "four zero-area faces")
  T.eq(T.bad_pixels(ib), 0, "NaN or infinite pixels")
end)

T.test("vertex normals shade smoothly; without them the face is flat", function()
  local tilted = {}
  for i = 1, 4 do tilted[i] = {0.6, 0.8, 0} end   -- unit, tilted toward +x
  local s1, s2 = top_scene(), top_scene()
  s1:add(lancer.mesh{vertices = SQUARE_V, faces = SQUARE_F, normals = tilted})
  s2:add(lancer.mesh{vertices = SQUARE_V, faces = SQUARE_F})
  local a = s1:render{width = 1, height = 1}:pixel(1, 1)
  local b = s2:render{width = 1, height = 1}:pixel(1, 1)
  T.near(b, 1.0, 1e-6, "flat: n.l = 1")
  T.near(a, 0.8, 1e-6, "smooth: n.l = 0.8")
end)

T.test("a scene keeps its mesh after the Lua value is gone", function()
  local s = top_scene()
  s:add(lancer.mesh{vertices = SQUARE_V, faces = SQUARE_F})
  collectgarbage()
  collectgarbage()
  T.near(select(1, s:render{width = 1, height = 1}:pixel(1, 1)), 1.0, 1e-6, "still there")
end)

T.test("mesh errors name the function, the field and the face", function()
  T.check_error(function() lancer.mesh{vertices = SQUARE_V, faces = {{1, 2, 5}}} end,
                HERE, "'mesh'", "field 'faces'", "face 1", "vertex index 5 out of range")
  T.check_error(function() lancer.mesh{vertices = SQUARE_V, faces = {{1, 2}}} end,
                HERE, "'mesh'", "field 'faces'", "at least 3 vertices")
  T.check_error(function() lancer.mesh{vertices = {{0, 0 / 0, 0}}} end,
                HERE, "'mesh'", "field 'vertices'", "point 1", "NaN in component 2")
  T.check_error(function() lancer.mesh{vertices = {0, 1}} end,
                HERE, "'mesh'", "field 'vertices'", "multiple of 3")
  T.check_error(function() lancer.mesh{vertices = SQUARE_V, faces = {1, 2, 3.5}} end,
                HERE, "'mesh'", "field 'faces'", "integer vertex index expected")
  T.check_error(function() lancer.mesh{vertices = SQUARE_V, faces = SQUARE_F,
                                       normals = {{0, 0, 0}}} end,
                HERE, "'mesh'", "field 'normals'", "zero-length")
  T.check_error(function() lancer.mesh{vertexes = {}} end,
                HERE, "'mesh'", "did you mean 'vertices'?")
  T.check_error(function() lancer.triangle{a = {0, 0, 0}, b = {1, 0, 0}} end,
                HERE, "'triangle'", "field 'c'")
  local m = lancer.mesh{vertices = SQUARE_V, faces = SQUARE_F, normals = {{0, 1, 0}}}
  local s = top_scene()
  T.check_error(function() s:add(m) end, HERE, "'add'", "1 normals for 4 vertices")
end)

-- Writes text to a fresh temporary .obj file and returns its path.
local function obj_file(text)
  local path = os.tmpname() .. ".obj"
  local f = assert(io.open(path, "w"))
  f:write(text)
  f:close()
  return path
end

T.test("load_obj: v, vn, vt, f forms, negative indices, polygons, other lines", function()
  local path = obj_file([[
# a square in four vertices, written every way OBJ allows
mtllib nothing.mtl
o square
v -1 0 -1
v 1 0 -1
v 1 0 1 1.0
v -1 0 1
vt 0 0
vn 0 1 0
g top
usemtl white
s off
f 1/1/1 2/1/1 -2/1/1
f -4//1 3//1 4//1
]])
  local m = lancer.load_obj(path)
  os.remove(path)
  T.eq(m.face_count, 2, "faces")
  local a, b = top_scene(), top_scene()
  a:add(m)
  b:add(lancer.mesh{vertices = SQUARE_V, faces = SQUARE_F})
  same_image(a:render{width = 16, height = 16}, b:render{width = 16, height = 16}, "obj")
  local p2 = obj_file("v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 1 2 3 4\n")
  local q = lancer.load_obj(p2, {material = lancer.material{color = 0.5}})
  os.remove(p2)
  T.eq(q.face_count, 2, "polygon as a fan")
  T.eq(q.material.color[1], 0.5, "material option")
end)

T.test("load_obj: malformed lines name the file and the line", function()
  local cases = {
    {"v 1 2\n", ":1: 'v' needs 3 finite numbers"},
    {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", ":4: vertex index out of range ('4')"},
    {"v 0 0 0\nv 1 0 0\nf 1 2\n", ":3: a face needs at least 3 vertices, got 2"},
    {"v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 x\n", ":5: expected a vertex index ('x')"},
    {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//2 2//2 3//2\n", ":4: normal index out of range"},
    {"v 0 nan 0\n", ":1: 'v' needs 3 finite numbers"},
  }
  for _, c in ipairs(cases) do
    local path = obj_file(c[1])
    local name = path:match("[^/]+$")
    T.check_error(function() lancer.load_obj(path) end, HERE, "'load_obj'", name .. c[2])
    os.remove(path)
  end
  T.check_error(function() lancer.load_obj("/nonexistent/x.obj") end, HERE, "'load_obj'",
                "cannot open '/nonexistent/x.obj'")
end)

T.test("load_png reads back what save wrote", function()
  local s = lancer.scene{background = {0.25, 0.5, 1}, camera = lancer.camera{
    from = {0, 0, 0}, at = {0, 0, 1}}}
  local img = s:render{width = 3, height = 2}
  local path = os.tmpname() .. ".png"
  img:save(path, {encoding = "linear"})
  local back = lancer.load_png(path, {encoding = "linear"})
  os.remove(path)
  local d = img:diff(back, 0.5 / 255 + 1e-6)
  T.eq(d.within, 1, "every pixel within half a step")
  T.check_error(function() lancer.load_png("/nonexistent.png") end, HERE, "'load_png'",
                "cannot open")
end)
