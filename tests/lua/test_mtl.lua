-- test_mtl.lua: a material per face: OBJ usemtl and mtllib with .mtl files
-- (colours, a map_Kd texture), overrides by name, and mesh{materials,
-- face_materials} built in Lua.
local T = require "harness"
local lancer = require "lancer"

local HERE = "test_mtl.lua:"

-- Two unit quads side by side at z = 0, x in [-1, 0] and [0, 1].
local QUADS = [[
v -1 0 0
v 0 0 0
v 0 1 0
v -1 1 0
v 1 0 0
v 1 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
]]

-- Ambient light only and ka = 1: a pixel reads its material's colour.
local function look(mesh)
  local s = lancer.scene{camera = lancer.camera{from = {0, 0.5, -3}, at = {0, 0.5, 0},
                                                fov = 60}, ambient = 1}
  s:add(mesh)
  local img = s:render{width = 8, height = 4}
  -- +x is on the left looking along +z: the quad at x < 0 is on the right;
  -- the quads fill pixels 3 to 6 of the 8.
  return {img:pixel(6, 2)}, {img:pixel(3, 2)}
end

local function same(got, want, what)
  for i = 1, 3 do T.near(got[i], want[i], 1e-6, what .. " channel " .. i) end
end

T.test("load_obj: usemtl faces take their .mtl materials, a map_Kd its texture", function()
  local dir = T.temp_dir()
  local green = lancer.image{width = 2, height = 2, color = {0, 1, 0}}
  green:save(dir .. "/leaf.png")
  T.write(dir .. "/model.mtl", [[
# two materials
newmtl red
Ka 1 1 1
Kd 1 0 0
newmtl leafy
Ka 1 1 1
Kd 1 1 1
map_Kd leaf.png
]])
  T.write(dir .. "/model.obj", "mtllib model.mtl\n" .. QUADS .. [[
usemtl red
f 1/1 2/2 3/3 4/4
usemtl leafy
f 2/1 5/2 6/3 3/4
]])
  local m = lancer.load_obj(dir .. "/model.obj")
  T.eq(m.material_names[1], "red", "slot 1's name")
  T.eq(m.material_names[2], "leafy", "slot 2's name")
  T.eq(m.materials[1].color[1], 1, "red's Kd")
  T.eq(m.materials[1].absorb, "diffuse", "highlights in the light's colour")
  T.eq(m.materials[2].color.kind, "image_texture", "leafy's colour is its map")
  local left, right = look(m)
  same(left, {1, 0, 0}, "the red quad")
  same(right, {0, 1, 0}, "the textured quad")
  -- Overridden by name, and without textures.
  local blue = lancer.material{color = {0, 0, 1}, ka = 1, kd = 0}
  left, right = look(lancer.load_obj(dir .. "/model.obj", {materials = {red = blue}}))
  same(left, {0, 0, 1}, "red overridden by name")
  same(right, {0, 1, 0}, "leafy as the file says")
  left, right = look(lancer.load_obj(dir .. "/model.obj", {textures = false}))
  same(right, {1, 1, 1}, "textures = false: Kd alone")
  -- Faces before any usemtl, or with a name no library has: the mesh's own.
  T.write(dir .. "/plain.obj", "mtllib model.mtl\n" .. QUADS .. [[
f 1/1 2/2 3/3 4/4
usemtl nowhere
f 2/1 5/2 6/3 3/4
]])
  local own = lancer.material{color = {0.5, 0.25, 1}, ka = 1, kd = 0}
  left, right = look(lancer.load_obj(dir .. "/plain.obj", {material = own}))
  same(left, {0.5, 0.25, 1}, "before usemtl")
  same(right, {0.5, 0.25, 1}, "a name found nowhere")
end)

T.test("load_obj: an .mtl norm map becomes a normal map, its values read as data", function()
  local dir = T.temp_dir()
  -- Stored 255, 128, 128: a normal leaning along dp/du by 45 degrees.
  local lean = lancer.image{width = 1, height = 1, color = {1, 0.5, 0.5}}
  lean:save(dir .. "/lean.png", {encoding = "linear"})
  T.write(dir .. "/n.mtl", "newmtl bent\nKd 1 1 1\nnorm lean.png\n")
  T.write(dir .. "/n.obj", "mtllib n.mtl\n" .. QUADS .. "usemtl bent\nf 1/1 2/2 3/3 4/4\n")
  local m = lancer.load_obj(dir .. "/n.obj")
  local mat = m.materials[1]
  T.eq(mat.normal_map.kind, "image_texture", "norm is the normal map")
  T.eq(mat.normal_scale, 1, "at full strength")
  T.eq(mat.color[1], 1, "the colour stays Kd")
  T.eq(#m.warnings, 0, "no warning")
end)

T.test("load_obj: .mtl errors name the file and the line; a missing map names it", function()
  local dir = T.temp_dir()
  T.write(dir .. "/a.obj", "mtllib a.mtl\n" .. QUADS .. "usemtl x\nf 1 2 3\n")
  -- A library that is not there: the mesh loads, its faces take its own
  -- material, and the mesh says what it left out.
  local alone = lancer.load_obj(dir .. "/a.obj")
  T.eq(alone.materials[1], false, "slot x: the mesh's own")
  assert(alone.warnings[1]:find("mtllib cannot open '" .. dir .. "/a.mtl'", 1, true),
         alone.warnings[1])
  T.write(dir .. "/a.mtl", "newmtl x\nKd 1 0\nKs one\n")
  T.check_error(function() lancer.load_obj(dir .. "/a.obj") end, "a.mtl:3: 'Ks' needs "
                .. "finite numbers")
  T.write(dir .. "/a.mtl", "newmtl x\nmap_Kd -s 2 2 2 missing.png\n")
  local partial = lancer.load_obj(dir .. "/a.obj")
  assert(partial.warnings[1]:find("material 'x': map_Kd '" .. dir .. "/missing.png' "
         .. "cannot be opened", 1, true), partial.warnings[1])
  T.eq(type(partial.materials[1].color), "table", "without its map: Kd")
  T.write(dir .. "/missing.png", "not a png")
  T.check_error(function() lancer.load_obj(dir .. "/a.obj") end, "material 'x': map_Kd",
                "not a PNG file")
  local m = lancer.load_obj(dir .. "/a.obj", {textures = false})
  T.near(m.materials[1].color[1], 0.8, 1e-7, "the format's default Kd")
  T.check_error(function() lancer.load_obj(dir .. "/a.obj", {materials = {x = 3}}) end,
                HERE, "field 'materials'", "'x': lancer.Material expected")
  T.write(dir .. "/b.obj", QUADS .. "usemtl\nf 1 2 3\n")
  T.check_error(function() lancer.load_obj(dir .. "/b.obj") end,
                "b.obj:11: 'usemtl' needs a material name")
end)

T.test("load_obj: .mtl numbers past what lancer keeps name the file, line, field", function()
  local dir = T.temp_dir()
  T.write(dir .. "/c.obj", "mtllib c.mtl\n" .. QUADS .. "usemtl x\nf 1 2 3\n")
  -- An int cannot hold 1e300 (converting it was undefined behaviour); a
  -- float cannot either (Ke 1e300 was an infinite emission, refused later
  -- by scene:add without naming the .mtl).
  local cases = {
    {"illum 1e300", "c.mtl:2: 'illum' needs an integer from -2147483648 to "
     .. "2147483647, not 1e+300"},
    {"illum -3e9", "c.mtl:2: 'illum' needs an integer from -2147483648 to "
     .. "2147483647, not -3e+09"},
    {"Ke 1e300", "c.mtl:2: 'Ke' needs numbers a float holds (to 3.40282e+38), "
     .. "not 1e+300"},
    {"Kd 0.5 -1e39 0", "c.mtl:2: 'Kd' needs numbers a float holds (to "
     .. "3.40282e+38), not -1e+39"},
    {"Ks 4e38", "c.mtl:2: 'Ks' needs numbers a float holds"},
    {"Ka 1 1 1e40", "c.mtl:2: 'Ka' needs numbers a float holds"},
    {"map_Bump -bm huge b.png", "c.mtl:2: 'map_Bump' needs a finite number after -bm"},
  }
  for _, c in ipairs(cases) do
    T.write(dir .. "/c.mtl", "newmtl x\n" .. c[1] .. "\n")
    local msg = T.check_error(function() lancer.load_obj(dir .. "/c.obj") end, c[2])
    assert(msg:find(dir .. "/c.mtl:2:", 1, true), msg)
  end
  -- The edges themselves load.
  T.write(dir .. "/c.mtl", "newmtl x\nillum 2147483647\nKe 3.4e38 0 1e-300\n")
  local m = lancer.load_obj(dir .. "/c.obj", {textures = false})
  T.near(m.materials[1].emission[1], 3.4e38, 1e32, "Ke at a float's edge")
  T.write(dir .. "/c.mtl", "newmtl x\nillum -2147483648\n")
  T.eq(lancer.load_obj(dir .. "/c.obj").materials[1].kr, 0, "illum at int's low end")
end)

T.test("lc_mtl_material's mapping: transparency, mirrors, emission, exponents", function()
  local dir = T.temp_dir()
  T.write(dir .. "/m.mtl", [[
newmtl glass
Kd 0.2 0.2 0.2
Ks 0.5 0.5 0.5
Ns 96
Ni 1.45
d 0.25
illum 4
newmtl lamp
Ke 4 3 2
Tr 0
]])
  T.write(dir .. "/m.obj", "mtllib m.mtl\n" .. QUADS .. "usemtl glass\nf 1 2 3\n" ..
          "usemtl lamp\nf 2 5 6\n")
  local ms = lancer.load_obj(dir .. "/m.obj").materials
  local g, l = ms[1], ms[2]
  T.eq(g.kt, 0.75, "kt = 1 - d")
  T.near(g.kd, 0.25, 1e-15, "kd = d")
  T.eq(g.ior, 1.45, "ior = Ni")
  T.eq(g.ks, 0.5, "ks = max(Ks)")
  T.eq(g.kr, 0.5, "illum 4 mirrors with Ks")
  T.eq(g.alpha, 96, "alpha = Ns")
  T.eq(l.emission[1], 4, "emission = Ke")
  T.eq(l.kt, 0, "Tr 0: opaque")
  T.eq(l.kr, 0, "no illum: no mirror")
end)

T.test("mesh{materials, face_materials}: one entry per face given, polygons included", function()
  local red = lancer.material{color = {1, 0, 0}, ka = 1, kd = 0}
  local green = lancer.material{color = {0, 1, 0}, ka = 1, kd = 0}
  local m = lancer.mesh{
    vertices = {{-1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {-1, 1, 0}, {1, 0, 0}, {1, 1, 0}},
    faces = {{1, 2, 3, 4}, {2, 5, 6, 3}},      -- two quads, four triangles
    materials = {red, green}, face_materials = {2, 1}}
  T.eq(m.face_count, 4, "fans")
  local left, right = look(m)
  same(left, {0, 1, 0}, "face 1 takes material 2")
  same(right, {1, 0, 0}, "face 2 takes material 1")
  -- A copy of the scene keeps the materials.
  local s = lancer.scene{camera = lancer.camera{from = {0, 0.5, -3}, at = {0, 0.5, 0}},
                         ambient = 1}
  s:add(m, m:moved(lancer.translate(0, 5, 0)))
  local a = s:render{width = 8, height = 4}
  local b = s:transformed(2):render{width = 8, height = 4}
  T.eq(a:diff(b, 1e-6).within, 1, "transformed keeps face materials")
  T.check_error(function() lancer.mesh{vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
    faces = {{1, 2, 3}}, materials = {red}, face_materials = {2}} end, HERE,
    "field 'face_materials'", "face 1: an index into materials (1..1)")
  T.check_error(function() lancer.mesh{vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
    faces = {{1, 2, 3}}, materials = {red}, face_materials = {1, 1}} end, HERE,
    "2 entries for 1 faces")
  T.check_error(function() lancer.mesh{faces = {}, face_materials = {}} end, HERE,
    "needs 'materials'")
  T.check_error(function() lancer.mesh{materials = {red, 7}} end, HERE,
    "field 'materials'", "entry 2: lancer.Material expected")
end)
