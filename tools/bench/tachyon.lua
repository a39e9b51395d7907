-- tachyon.lua: writes a scenes.lua scene as a Tachyon 0.99 file; how to render it.
--
-- docs/bench-scenes.md's rules: Tachyon is left-handed with no switch, so every x is
-- negated (the mirrored scene gives the same image); ZOOM = 0.5 (W/H) /
-- tan(hfov/2) with ASPECTRATIO 1; RAYDEPTH = depth + 1; a material is
-- AMBIENT ka DIFFUSE kd SPECULAR kr (Tachyon's SPECULAR is the mirror
-- coefficient) PHONG PLASTIC ks PHONG_SIZE n, rendered with -shade_phong;
-- lights are tiny spheres (RAD 0.0001, under a pixel); B3 is a list of TRI.
local T = {}

local fmt = string.format

local function num(x) return fmt("%.10g", x) end
-- A point or direction, mirrored (x -> -x).
local function mvec(v) return fmt("%s %s %s", num(0.0 - v[1]), num(v[2]), num(v[3])) end
local function rgb(c) return fmt("%s %s %s", num(c[1]), num(c[2]), num(c[3])) end

local function sub(a, b) return {a[1] - b[1], a[2] - b[2], a[3] - b[3]} end
local function cross(a, b)
  return {a[2] * b[3] - a[3] * b[2], a[3] * b[1] - a[1] * b[3], a[1] * b[2] - a[2] * b[1]}
end
local function normalize(a)
  local l = math.sqrt(a[1] * a[1] + a[2] * a[2] + a[3] * a[3])
  return {a[1] / l, a[2] / l, a[3] / l}
end

local function write_header(f, scene)
  local c = scene.camera
  -- docs/bench-scenes.md's basis: f forward, r = f x up, u = r x f. Tachyon gets f and
  -- the true (orthogonal) up, both mirrored with the scene.
  local fwd = normalize(sub(c.target, c.eye))
  local right = normalize(cross(fwd, c.up))
  local up = cross(right, fwd)
  local zoom = 0.5 * (scene.width / scene.height) / math.tan(math.rad(c.hfov) / 2)
  f:write("BEGIN_SCENE\n")
  f:write(fmt("RESOLUTION %d %d\n", scene.width, scene.height))
  f:write("CAMERA\n  PROJECTION PERSPECTIVE\n")
  f:write(fmt("  ZOOM %s\n  ASPECTRATIO 1.0\n  ANTIALIASING 0\n  RAYDEPTH %d\n",
              num(zoom), scene.depth + 1))
  f:write(fmt("  CENTER %s\n  VIEWDIR %s\n  UPDIR %s\nEND_CAMERA\n",
              mvec(c.eye), mvec(fwd), mvec(up)))
  f:write(fmt("BACKGROUND %s\n", rgb(scene.background)))
  for _, l in ipairs(scene.lights) do
    f:write(fmt("LIGHT CENTER %s RAD 0.0001 COLOR %s\n", mvec(l.position), rgb(l.color)))
  end
  local names = {}                   -- sorted: the same file every time
  for name in pairs(scene.materials) do names[#names + 1] = name end
  table.sort(names)
  for _, name in ipairs(names) do
    local m = scene.materials[name]
    f:write(fmt("TEXDEF %s AMBIENT %s DIFFUSE %s SPECULAR %s OPACITY 1.0\n" ..
                "  PHONG PLASTIC %s PHONG_SIZE %s COLOR %s TEXFUNC 0\n",
                name, num(m.ka), num(m.kd), num(m.kr), num(m.ks),
                num(m.n > 0 and m.n or 1), rgb(m.color)))
  end
end

-- B3's grid as TRI records: each vertex formatted once, mirrored, then
-- pasted into the (up to six) triangles that share it, two rows at a time.
local function write_mesh(f, scene, grid)
  local mesh = scene.mesh
  local q, tex = mesh.q, " " .. mesh.material .. "\n"
  local function row_of(j)
    local row = {}
    for i = 0, q do
      local x, y, z = grid(mesh, i, j)
      row[i] = fmt("%.5f %.5f %.5f", -x, y, z)
    end
    return row
  end
  local lo = row_of(0)
  for j = 0, q - 1 do
    local hi = row_of(j + 1)
    local out = {}
    for i = 0, q - 1 do
      local v00, v10, v01, v11 = lo[i], lo[i + 1], hi[i], hi[i + 1]
      out[#out + 1] = "TRI V0 " .. v00 .. " V1 " .. v10 .. " V2 " .. v11 .. tex
      out[#out + 1] = "TRI V0 " .. v00 .. " V1 " .. v11 .. " V2 " .. v01 .. tex
    end
    f:write(table.concat(out))
    lo = hi
  end
end

-- The scene classes' cylinders (FCYLINDER: open, BASE and APEX), quads (two
-- TRIs), triangles and instances (Tachyon has none: each placed copy's
-- triangles are written out).
local function tri(a, b, c, m)
  return fmt("TRI V0 %s V1 %s V2 %s %s\n", mvec(a), mvec(b), mvec(c), m)
end

local function write_classes(f, scene)
  for _, c in ipairs(scene.cylinders or {}) do
    f:write(fmt("FCYLINDER BASE %s APEX %s RAD %s %s\n", mvec(c.base), mvec(c.top),
                num(c.radius), c.material))
  end
  for _, q in ipairs(scene.quads or {}) do
    local p, u, v = q.corner, q.u, q.v
    local pu = {p[1] + u[1], p[2] + u[2], p[3] + u[3]}
    local puv = {pu[1] + v[1], pu[2] + v[2], pu[3] + v[3]}
    local pv = {p[1] + v[1], p[2] + v[2], p[3] + v[3]}
    f:write(tri(p, pu, puv, q.material), tri(p, puv, pv, q.material))
  end
  for _, t in ipairs(scene.triangles or {}) do f:write(tri(t.a, t.b, t.c, t.material)) end
  local inst = scene.instances
  if not inst then return end
  local v, faces = inst.vertices, inst.faces
  for _, m in ipairs(inst.placements) do
    local moved = {}
    for i = 1, #v, 3 do
      local x, y, z = v[i], v[i + 1], v[i + 2]
      moved[(i + 2) // 3] = {m[1][1] * x + m[1][2] * y + m[1][3] * z + m[1][4],
                             m[2][1] * x + m[2][2] * y + m[2][3] * z + m[2][4],
                             m[3][1] * x + m[3][2] * y + m[3][3] * z + m[3][4]}
    end
    local out = {}
    for i = 1, #faces, 3 do
      out[#out + 1] = tri(moved[faces[i]], moved[faces[i + 1]], moved[faces[i + 2]],
                          inst.material)
    end
    f:write(table.concat(out))
  end
end

-- Writes scene to path (through path .. ".tmp", renamed at the end, so a
-- file that exists is complete). grid is scenes.grid_vertex.
function T.write(scene, path, grid)
  for name, m in pairs(scene.materials) do
    -- Tachyon's transmission ray goes on along the incident ray and its
    -- .dat has no index of refraction: glass is beyond it. (The writer has
    -- no checker either: the only scene with one has glass.)
    assert(not m.kt and not m.checker, "tachyon.lua: material '" .. name ..
           "' has kt or a checker, which this writer cannot say")
  end
  local tmp = path .. ".tmp"
  local f = assert(io.open(tmp, "w"))
  write_header(f, scene)
  for _, p in ipairs(scene.planes) do
    f:write(fmt("PLANE CENTER %s NORMAL %s %s\n", mvec(p.point), mvec(p.normal),
                p.material))
  end
  for _, b in ipairs(scene.boxes) do
    -- Mirroring swaps which x is the smaller.
    f:write(fmt("BOX MIN %s %s %s MAX %s %s %s %s\n", num(-b.max[1]), num(b.min[2]),
                num(b.min[3]), num(-b.min[1]), num(b.max[2]), num(b.max[3]), b.material))
  end
  local d = scene.sphere_decimals
  local sfmt = "SPHERE CENTER %.10g %.10g %.10g RAD %.10g %s\n"
  if d then
    sfmt = fmt("SPHERE CENTER %%.%df %%.%df %%.%df RAD %%.%df %%s\n", d, d, d, d)
  end
  scene.spheres(function(x, y, z, r, m) f:write(fmt(sfmt, -x, y, z, r, m)) end)
  if scene.mesh then write_mesh(f, scene, grid) end
  write_classes(f, scene)
  f:write("END_SCENE\n")
  assert(f:close())
  assert(os.rename(tmp, path))
end

-- The command line (a list of words) rendering dat into png. 16 spp: the
-- centre plus 15 jittered samples.
function T.command(_, dat, png, samples, threads)
  local cmd = {"tachyon", dat, "-o", png, "-format", "PNG", "-shade_phong",
               "-numthreads", tostring(threads)}
  if samples > 1 then
    cmd[#cmd + 1] = "-aasamples"
    cmd[#cmd + 1] = tostring(samples - 1)
  end
  return cmd
end

-- Tachyon's own trace time from its log (the "Ray Tracing Time" line), or nil.
function T.render_seconds(log)
  return tonumber(log:match("Ray Tracing Time:%s*([%d.]+) seconds"))
end

return T
