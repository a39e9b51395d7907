-- povray.lua: writes a scenes.lua scene as a POV-Ray 3.7 file; how to render it.
--
-- docs/bench-scenes.md's rules: right-handed camera through `right -x*W/H`, point lights
-- without fade, finish { ambient kd phong reflection } (POV-Ray's colour
-- scales ambient and diffuse only, as the spec's shading does),
-- max_trace_level = depth + 1, no adaptive depth cut-off (adc_bailout 0),
-- linear output (assumed_gamma 1.0 in the file, File_Gamma=1.0 on the
-- command line). No #declare but the instanced mesh's: every object carries
-- its own texture, so the file is exactly what the scene says, object by
-- object.
local P = {}

local fmt = string.format

local function num(x) return fmt("%.10g", x) end
local function vec(v) return fmt("<%s, %s, %s>", num(v[1]), num(v[2]), num(v[3])) end

-- POV-Ray's checker is lancer's: cubes of side 1 in pigment space, the
-- first colour where floor(x) + floor(y) + floor(z) is even; `scale` makes
-- them scale wide. (POV-Ray 3.x's sources add a thousandth to each
-- coordinate before floor(); 3.7.0's images show none: moved by that
-- much, 0.1 % of the glass scene's pixels, along checker edges, differ.)
local function pigment(m)
  local c = m.checker
  if c then
    return fmt("pigment { checker rgb %s, rgb %s scale %s }", vec(c.a), vec(c.b),
               num(c.scale))
  end
  if m.kt then       -- transmit: what goes through, times the light behind
    return fmt("pigment { rgbt <%s, %s, %s, %s> }", num(m.color[1]), num(m.color[2]),
               num(m.color[3]), num(m.kt))
  end
  return fmt("pigment { rgb %s }", vec(m.color))
end

-- One texture per material, written out in full where each object needs it.
-- Glass (kt) is the fixed model: a transmit of kt and a reflection of kr
-- with no Fresnel and no conserve_energy, the interior giving the ior. On
-- a total internal reflection POV-Ray reflects at weight 1 and skips kr, so
-- kr + kt must be 1 for it to draw what lancer does (kr + kt reflected).
local function texture(m)
  local finish = {fmt("ambient %s diffuse %s", num(m.ka), num(m.kd))}
  if m.ks > 0 then
    finish[#finish + 1] = fmt("phong %s phong_size %s", num(m.ks), num(m.n))
  end
  if m.kr > 0 then finish[#finish + 1] = fmt("reflection { %s }", num(m.kr)) end
  local tex = fmt("texture { %s finish { %s } }", pigment(m), table.concat(finish, " "))
  if m.kt then
    assert(math.abs(m.kr + m.kt - 1) < 1e-12,
           "povray.lua: glass needs kr + kt = 1 (POV-Ray's total internal reflection)")
    tex = tex .. fmt(" interior { ior %s }", num(m.ior))
  end
  return tex
end
P.texture = texture

local function write_header(f, scene)
  local c = scene.camera
  f:write("// ", scene.name, ", written by lancer's tools/bench/povray.lua\n")
  f:write("#version 3.7;\n")
  f:write(fmt("global_settings { assumed_gamma 1.0 ambient_light rgb 1 " ..
              "max_trace_level %d adc_bailout 0 }\n", scene.depth + 1))
  -- look_at last: POV-Ray turns the right/up/direction vectors it has so far.
  f:write(fmt("camera { perspective location %s sky %s right -x*%d/%d up y angle %s " ..
              "look_at %s }\n", vec(c.eye), vec(c.up), scene.width, scene.height,
              num(c.hfov), vec(c.target)))
  f:write(fmt("background { rgb %s }\n", vec(scene.background)))
  for _, l in ipairs(scene.lights) do
    f:write(fmt("light_source { %s rgb %s }\n", vec(l.position), vec(l.color)))
  end
end

-- B3's grid as one mesh2: every vertex once, then the faces by index.
local function write_mesh(f, scene, grid)
  local mesh = scene.mesh
  local q = mesh.q
  f:write(fmt("mesh2 {\n vertex_vectors { %d,\n", (q + 1) * (q + 1)))
  for j = 0, q do
    local row = {}
    for i = 0, q do
      row[i + 1] = fmt("<%.5f,%.5f,%.5f>,", grid(mesh, i, j))
    end
    f:write(table.concat(row), "\n")
  end
  f:write(fmt(" }\n face_indices { %d,\n", 2 * q * q))
  for j = 0, q - 1 do
    local row = {}
    for i = 0, q - 1 do
      local v00 = j * (q + 1) + i
      local v10, v01 = v00 + 1, v00 + q + 1
      local v11 = v01 + 1
      row[#row + 1] = fmt("<%d,%d,%d>,<%d,%d,%d>,", v00, v10, v11, v00, v11, v01)
    end
    f:write(table.concat(row), "\n")
  end
  f:write(" }\n ", texture(scene.materials[mesh.material]), "\n}\n")
end

-- A CSG tree (scenes.lua's form): POV-Ray's own CSG of closed leaves, each
-- leaf with its texture (cut faces take the cutter's, as in lancer).
local function write_csg(f, node, tex, indent)
  if node.op then
    f:write(indent, node.op, " {\n")
    for _, c in ipairs(node) do write_csg(f, c, tex, indent .. "  ") end
    f:write(indent, "}\n")
    return
  end
  local t, sh = tex[node.material], node.shape
  if sh == "box" then
    f:write(fmt("%sbox { %s, %s %s }\n", indent, vec(node.min), vec(node.max), t))
  elseif sh == "sphere" then
    f:write(fmt("%ssphere { %s, %s %s }\n", indent, vec(node.center), num(node.radius),
                t))
  elseif sh == "cylinder" then
    f:write(fmt("%scylinder { %s, %s, %s %s }\n", indent, vec(node.base), vec(node.top),
                num(node.radius), t))
  elseif sh == "cone" then
    f:write(fmt("%scone { %s, %s, %s, %s %s }\n", indent, vec(node.base),
                num(node.base_radius), vec(node.top), num(node.top_radius), t))
  elseif sh == "torus" then       -- POV-Ray's torus lies around +y at the origin
    f:write(fmt("%storus { %s, %s %s translate %s }\n", indent, num(node.major),
                num(node.minor), t, vec(node.center)))
  else
    error("povray.lua: no CSG leaf '" .. tostring(sh) .. "'")
  end
end

-- The scene classes' open cylinders, quads (two triangles, as Tachyon
-- gets them), triangles, and instances: the one mesh2 declared once (the
-- only #declare, as POV-Ray shares a declared mesh's data among its
-- copies), each copy an object placed by its matrix.
local function write_classes(f, scene, tex)
  for _, c in ipairs(scene.cylinders or {}) do
    f:write(fmt("cylinder { %s, %s, %s open %s }\n", vec(c.base), vec(c.top),
                num(c.radius), tex[c.material]))
  end
  for _, q in ipairs(scene.quads or {}) do
    local p, u, v = q.corner, q.u, q.v
    local pu = {p[1] + u[1], p[2] + u[2], p[3] + u[3]}
    local puv = {pu[1] + v[1], pu[2] + v[2], pu[3] + v[3]}
    local pv = {p[1] + v[1], p[2] + v[2], p[3] + v[3]}
    f:write(fmt("triangle { %s, %s, %s %s }\ntriangle { %s, %s, %s %s }\n", vec(p),
                vec(pu), vec(puv), tex[q.material], vec(p), vec(puv), vec(pv),
                tex[q.material]))
  end
  for _, t in ipairs(scene.triangles or {}) do
    f:write(fmt("triangle { %s, %s, %s %s }\n", vec(t.a), vec(t.b), vec(t.c),
                tex[t.material]))
  end
  local inst = scene.instances
  if not inst then return end
  local v, faces = inst.vertices, inst.faces
  f:write(fmt("#declare Placed = mesh2 {\n vertex_vectors { %d,\n", #v // 3))
  for i = 1, #v, 3 do
    f:write(fmt(" <%s, %s, %s>,\n", num(v[i]), num(v[i + 1]), num(v[i + 2])))
  end
  f:write(fmt(" }\n face_indices { %d,\n", #faces // 3))
  for i = 1, #faces, 3 do
    f:write(fmt(" <%d, %d, %d>,\n", faces[i] - 1, faces[i + 1] - 1, faces[i + 2] - 1))
  end
  f:write(" }\n}\n")
  -- POV-Ray's matrix maps the row (x, y, z, 1): its entries are M's columns.
  for _, m in ipairs(inst.placements) do
    f:write(fmt("object { Placed %s matrix <%s, %s, %s, %s, %s, %s, %s, %s, %s, " ..
                "%s, %s, %s> }\n", tex[inst.material],
                num(m[1][1]), num(m[2][1]), num(m[3][1]), num(m[1][2]), num(m[2][2]),
                num(m[3][2]), num(m[1][3]), num(m[2][3]), num(m[3][3]), num(m[1][4]),
                num(m[2][4]), num(m[3][4])))
  end
end

-- Writes scene to path (through path .. ".tmp", renamed at the end, so a
-- file that exists is complete). grid is scenes.grid_vertex.
function P.write(scene, path, grid)
  local tmp = path .. ".tmp"
  local f = assert(io.open(tmp, "w"))
  write_header(f, scene)
  local tex = {}
  for name, m in pairs(scene.materials) do tex[name] = texture(m) end
  for _, p in ipairs(scene.planes) do
    local n = p.normal
    local d = n[1] * p.point[1] + n[2] * p.point[2] + n[3] * p.point[3]
    f:write(fmt("plane { %s, %s %s }\n", vec(n), num(d), tex[p.material]))
  end
  for _, b in ipairs(scene.boxes) do
    f:write(fmt("box { %s, %s %s }\n", vec(b.min), vec(b.max), tex[b.material]))
  end
  local d = scene.sphere_decimals
  local sfmt = "sphere { <%.10g, %.10g, %.10g>, %.10g %s }\n"
  if d then
    sfmt = fmt("sphere { <%%.%df, %%.%df, %%.%df>, %%.%df %%s }\n", d, d, d, d)
  end
  scene.spheres(function(x, y, z, r, m) f:write(fmt(sfmt, x, y, z, r, tex[m])) end)
  if scene.mesh then write_mesh(f, scene, grid) end
  write_classes(f, scene, tex)
  for _, tree in ipairs(scene.csg or {}) do write_csg(f, tree, tex, "") end
  assert(f:close())
  assert(os.rename(tmp, path))
end

-- The command line (a list of words) rendering pov into png, run from the
-- directory holding both (Debian's povray.conf allows writes to "." only).
-- 16 spp: a regular 4x4 grid on every pixel (threshold 0, method 1, no jitter).
function P.command(scene, pov, png, samples, threads)
  local cmd = {"povray", "+I" .. pov, "+O" .. png, "+W" .. scene.width,
               "+H" .. scene.height, "+FN", "-D", "+WT" .. threads, "File_Gamma=1.0",
               "-P"}
  if samples > 1 then
    assert(samples == 16, "POV-Ray runs 1 or 16 samples a pixel")
    for _, w in ipairs{"+A0.0", "+AM1", "+R4", "+J0"} do cmd[#cmd + 1] = w end
  else
    cmd[#cmd + 1] = "-A"
  end
  return cmd
end

-- POV-Ray's own trace time from its log (the "Trace Time" line), or nil.
function P.render_seconds(log)
  return tonumber(log:match("Trace Time:[^\n]-%(([%d.]+) seconds%)"))
end

return P
