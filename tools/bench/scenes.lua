-- scenes.lua: docs/bench-scenes.md's scenes B1, B2 and B3 and the scene classes (a city,
-- clusters, mixed primitives, instances) as plain data, for the peer writers.
--
-- lancer's own versions are scenes/bench/b*.lua, written against its API;
-- this file says the same thing once more in renderer-neutral terms so that
-- povray.lua and tachyon.lua write their files from one description. Keep
-- both in step with docs/bench-scenes.md, not with each other.
--
-- A scene is a table:
--   camera      {eye = {x,y,z}, target = {x,y,z}, up = {x,y,z}, hfov = degrees}
--   width, height, depth (mirror bounces), background {r,g,b}
--   lights      list of {position = {x,y,z}, color = {r,g,b}} (point lights, no falloff)
--   materials   name -> {color = {r,g,b}, ka, kd, ks, n, kr}; a material may
--               instead carry checker = {a = {r,g,b}, b = {r,g,b}, scale}
--               (cubes of side scale in world space, a where floor(x/scale) +
--               floor(y/scale) + floor(z/scale) is even) in place of color,
--               and glass kt (fixed transmission, no Fresnel) with ior
--   planes      list of {point, normal, material}
--   boxes       list of {min, max, material} (axis-aligned)
--   spheres(emit)  calls emit(x, y, z, r, material) for every sphere, in order
--   sphere_decimals  digits the writers give sphere numbers (nil: full precision)
--   mesh        nil or {q = Q, height = h(x, z), material} (B3's grid)
--   csg         nil or a list of trees: {op = "difference" | "intersection" |
--               "union" | "merge", operand, ...}, leaves {shape = "box", min, max},
--               {shape = "sphere", center, radius}, {shape = "cylinder", base,
--               top, radius}, {shape = "cone", base, top, base_radius,
--               top_radius} (both capped), {shape = "torus", center, major,
--               minor} (around +y), each with a material (scenes/csg.lua)
local M = {}

M.WIDTH, M.HEIGHT = 1280, 720

local function list_emitter(list)
  return function(emit)
    for _, s in ipairs(list) do emit(s[1], s[2], s[3], s[4], s[5]) end
  end
end

-- B1 "mirror room"; samples is chosen by the command line, not here.
function M.b1()
  local function m(c, ka, kd, ks, n, kr)
    return {color = c, ka = ka, kd = kd, ks = ks, n = n, kr = kr}
  end
  return {
    name = "b1",
    camera = {eye = {0, 2, 5.5}, target = {0, 1.2, -2}, up = {0, 1, 0}, hfov = 70},
    width = M.WIDTH, height = M.HEIGHT, depth = 3, background = {0, 0, 0},
    lights = {{position = {0, 4.5, 2.0}, color = {0.7, 0.7, 0.7}},
              {position = {-3, 3, -4.5}, color = {0.6, 0.35, 0.08}}},
    materials = {
      floor   = m({0.75, 0.72, 0.65}, 0.1, 0.7, 0, 0, 0.3),
      ceiling = m({0.90, 0.90, 0.90}, 0.1, 0.7, 0, 0, 0.3),
      left    = m({0.80, 0.30, 0.30}, 0.1, 0.7, 0, 0, 0.3),
      right   = m({0.30, 0.40, 0.80}, 0.1, 0.7, 0, 0, 0.3),
      back    = m({0.80, 0.80, 0.80}, 0.1, 0.7, 0, 0, 0.3),
      front   = m({0.60, 0.80, 0.60}, 0.1, 0.7, 0, 0, 0.3),
      mirror  = m({1, 1, 1},          0,   0,   0, 0, 0.9),
      green   = m({0.10, 0.80, 0.10}, 0.1, 0.9, 0, 0, 0),
      shiny   = m({0.95, 0.95, 0.95}, 0.1, 0.6, 0.8, 50, 0),
      boxm    = m({0.80, 0.55, 0.20}, 0.1, 0.8, 0, 0, 0),
    },
    planes = {
      {point = {0, 0, 0},  normal = {0, 1, 0},  material = "floor"},
      {point = {0, 5, 0},  normal = {0, -1, 0}, material = "ceiling"},
      {point = {-4, 0, 0}, normal = {1, 0, 0},  material = "left"},
      {point = {4, 0, 0},  normal = {-1, 0, 0}, material = "right"},
      {point = {0, 0, -6}, normal = {0, 0, 1},  material = "back"},
      {point = {0, 0, 6},  normal = {0, 0, -1}, material = "front"},
    },
    boxes = {{min = {1.0, 0.0, -4.4}, max = {2.6, 1.6, -2.8}, material = "boxm"}},
    spheres = list_emitter{{-1.6, 1.2, -2.0, 1.2, "mirror"},
                           {1.8, 0.8, -0.5, 0.8, "green"},
                           {0.2, 0.7, 1.2, 0.7, "shiny"}},
  }
end

-- B2 "many spheres": n spheres from the PRNG of docs/bench-scenes.md (seed 1) on
-- a ground plane.
local PALETTE = {{0.9, 0.2, 0.2}, {0.2, 0.9, 0.2}, {0.2, 0.3, 0.9}, {0.9, 0.9, 0.2},
                 {0.9, 0.2, 0.9}, {0.2, 0.9, 0.9}, {0.95, 0.95, 0.95}, {0.9, 0.5, 0.1}}

function M.b2(n)
  local materials = {
    ground = {color = {0.6, 0.6, 0.6}, ka = 0.1, kd = 0.8, ks = 0, n = 0, kr = 0}}
  for k, c in ipairs(PALETTE) do
    materials["p" .. (k - 1)] = {color = c, ka = 0.1, kd = 0.8, ks = 0, n = 0, kr = 0}
  end
  local function spheres(emit)
    local s = 1                      -- the LCG; Lua integers wrap mod 2^64
    local function u()
      s = s * 6364136223846793005 + 1442695040888963407
      return (s >> 11) * (1.0 / 9007199254740992.0)
    end
    for k = 0, n - 1 do
      local x = -50 + 100 * u()
      local z = -50 + 100 * u()
      local r = 0.05 + 0.25 * u()
      emit(x, r, z, r, "p" .. (k % 8))
    end
  end
  return {
    name = "b2",
    camera = {eye = {0, 12, 62}, target = {0, 0, 0}, up = {0, 1, 0}, hfov = 60},
    width = M.WIDTH, height = M.HEIGHT, depth = 3, background = {0.5, 0.7, 1.0},
    lights = {{position = {40, 60, 30}, color = {1, 1, 1}}},
    materials = materials,
    planes = {{point = {0, 0, 0}, normal = {0, 1, 0}, material = "ground"}},
    boxes = {},
    spheres = spheres,
    sphere_decimals = 5,             -- the peers' files: centre and radius, 5 decimals
  }
end

-- B3 "mesh": a q x q height field, 2 triangles a quad.
local sin, cos = math.sin, math.cos
local function height(x, z)
  return 3.0 * sin(0.11 * x) * cos(0.13 * z)
       + 1.2 * sin(0.37 * x + 1.0) * sin(0.29 * z + 2.0)
       + 0.35 * sin(1.3 * x + 0.3) * cos(1.7 * z + 0.7)
       + 0.1 * sin(5.1 * x) * cos(4.3 * z)
end

function M.b3(q)
  return {
    name = "b3",
    camera = {eye = {0, 14, 62}, target = {0, 0, 0}, up = {0, 1, 0}, hfov = 60},
    width = M.WIDTH, height = M.HEIGHT, depth = 3, background = {0.5, 0.7, 1.0},
    lights = {{position = {60, 25, 20}, color = {1, 1, 1}}},
    materials = {terrain = {color = {0.55, 0.65, 0.40}, ka = 0.1, kd = 0.8, ks = 0, n = 0,
                            kr = 0}},
    planes = {}, boxes = {},
    spheres = list_emitter{},
    mesh = {q = q, height = height, material = "terrain"},
  }
end

-- "CSG": the classic (a box and a sphere intersected, three cylinders drilled
-- out), a torus ring cut open by a box, a lathe-like stack of cones merged
-- with a sphere, a die (a cube rounded by a sphere, dimpled by spheres) on
-- a reflecting floor just below them, two lights. No two surfaces of a tree
-- coincide: POV-Ray shows noise there, and the comparison is about what
-- both draw alike. lancer's version is scenes/csg.lua.
function M.csg()
  local function m(c, ka, kd, ks, n, kr)
    return {color = c, ka = ka, kd = kd, ks = ks, n = n, kr = kr}
  end
  local function cyl(c, a, r, mat)
    return {shape = "cylinder", base = {c[1] - a[1], c[2] - a[2], c[3] - a[3]},
            top = {c[1] + a[1], c[2] + a[2], c[3] + a[3]}, radius = r, material = mat}
  end
  local classic = {op = "difference",
    {op = "intersection",
     {shape = "box", min = {-1, 0, -1}, max = {1, 2, 1}, material = "red"},
     {shape = "sphere", center = {0, 1, 0}, radius = 1.32, material = "gold"}},
    cyl({0, 1, 0}, {1.5, 0, 0}, 0.52, "blue"), cyl({0, 1, 0}, {0, 1.5, 0}, 0.52, "blue"),
    cyl({0, 1, 0}, {0, 0, 1.5}, 0.52, "blue")}
  local ring = {op = "difference",
    {shape = "torus", center = {-3.2, 0.45, 1.2}, major = 1.05, minor = 0.45,
     material = "green"},
    {shape = "box", min = {-3.3, -0.5, 1.3}, max = {-1.5, 1.5, 3}, material = "gold"}}
  local function cone(y0, y1, r0, r1)
    return {shape = "cone", base = {3.2, y0, 1.2}, top = {3.2, y1, 1.2},
            base_radius = r0, top_radius = r1, material = "white"}
  end
  local lathe = {op = "merge",
    cone(0, 0.25, 0.9, 0.8), cone(0.22, 1.3, 0.75, 0.3), cone(1.25, 1.6, 0.32, 0.55),
    cone(1.55, 2.3, 0.5, 0.15),
    {shape = "sphere", center = {3.2, 2.45, 1.2}, radius = 0.28, material = "white"}}
  local die = {op = "difference",
    {op = "intersection",
     {shape = "box", min = {-2.5, 0, -3.4}, max = {-1.1, 1.4, -2},
      material = "white"},
     {shape = "sphere", center = {-1.8, 0.7, -2.7}, radius = 0.95, material = "white"}},
    {shape = "sphere", center = {-1.8, 0.7, -3.65}, radius = 0.33, material = "red"},
    {shape = "sphere", center = {-2.1, 1.65, -3.0}, radius = 0.3, material = "red"},
    {shape = "sphere", center = {-1.5, 1.65, -2.4}, radius = 0.3, material = "red"},
    {shape = "sphere", center = {-0.85, 0.4, -3.0}, radius = 0.28, material = "red"},
    {shape = "sphere", center = {-0.85, 1.0, -2.4}, radius = 0.28, material = "red"}}
  return {
    name = "csg",
    camera = {eye = {0.6, 4.4, -8.5}, target = {0, 0.9, 0}, up = {0, 1, 0}, hfov = 62},
    width = M.WIDTH, height = M.HEIGHT, depth = 3, background = {0.45, 0.55, 0.7},
    lights = {{position = {-5, 9, -7}, color = {0.8, 0.8, 0.8}},
              {position = {6, 5, -3}, color = {0.35, 0.3, 0.25}}},
    materials = {
      floor = m({0.7, 0.7, 0.68}, 0.1, 0.7, 0, 0, 0.25),
      red   = m({0.85, 0.2, 0.15}, 0.1, 0.8, 0.4, 40, 0),
      gold  = m({0.9, 0.7, 0.25}, 0.1, 0.8, 0.6, 60, 0),
      blue  = m({0.2, 0.4, 0.9}, 0.1, 0.8, 0, 0, 0),
      green = m({0.25, 0.75, 0.35}, 0.1, 0.8, 0.3, 30, 0),
      white = m({0.92, 0.92, 0.9}, 0.1, 0.8, 0.5, 50, 0.15),
    },
    -- just under the solids standing on it: no face of theirs lies in it
    planes = {{point = {0, -0.01, 0}, normal = {0, 1, 0}, material = "floor"}},
    boxes = {},
    spheres = list_emitter{},
    csg = {classic, ring, lathe, die},
  }
end

-- ---- scene classes: a city, clusters, mixed primitives, instances ----------
-- Each is scenes/bench/<name>.lua in lancer's API, drawn from the same
-- PRNG in the same order; the image columns check that both say the same.
-- Fields beyond B1-B3's: cylinders {base, top, radius, material} (open: no
-- caps, as Tachyon's FCYLINDER), quads {corner, u, v, material} (the peers
-- get two triangles), triangles {a, b, c, material}, instances {vertices,
-- faces (flat lists, faces 1-based), material, placements (3x4 rows {M | t})}.

-- The benchmark's PRNG (B2's LCG), seeded.
local function lcg(seed)
  local s = seed
  return function()
    s = s * 6364136223846793005 + 1442695040888963407
    return (s >> 11) * (1.0 / 9007199254740992.0)
  end
end

local function palette_materials(extra)
  local materials = extra or {}
  for k, c in ipairs(PALETTE) do
    materials["p" .. (k - 1)] = {color = c, ka = 0.1, kd = 0.8, ks = 0, n = 0, kr = 0}
  end
  materials.ground = {color = {0.6, 0.6, 0.6}, ka = 0.1, kd = 0.8, ks = 0, n = 0, kr = 0}
  return materials
end

local function open_air(name, camera, lights, extra)
  local scene = {name = name, camera = camera, width = M.WIDTH, height = M.HEIGHT,
                 depth = 3, background = {0.5, 0.7, 1.0}, lights = lights,
                 materials = palette_materials(),
                 planes = {{point = {0, 0, 0}, normal = {0, 1, 0}, material = "ground"}},
                 boxes = {}, spheres = list_emitter{}}
  for k, v in pairs(extra) do scene[k] = v end
  return scene
end

-- "city": an L x L grid of lots, every eighth row and column a street; a
-- building a lot, its footprint and height random, taller toward the middle.
function M.city(L)
  local u, boxes = lcg(7), {}
  for i = 0, L - 1 do
    for j = 0, L - 1 do
      if i % 8 ~= 0 and j % 8 ~= 0 then
        local cx, cz = i - L / 2 + 0.5, j - L / 2 + 0.5
        local w, d = 0.55 + 0.4 * u(), 0.55 + 0.4 * u()
        local near = math.max(0, 1 - math.sqrt(cx * cx + cz * cz) / (L / 2))
        local h = 0.3 + 0.5 * u() + 12 * near * near * u()
        boxes[#boxes + 1] = {min = {cx - w / 2, 0, cz - d / 2},
                             max = {cx + w / 2, h, cz + d / 2},
                             material = "p" .. ((i * L + j) % 8)}
      end
    end
  end
  return open_air("city", {eye = {0, 0.3 * L, 0.6 * L}, target = {0, 0, 0}, up = {0, 1, 0},
                           hfov = 50},
                  {{position = {0.4 * L, 0.6 * L, 0.25 * L}, color = {1, 1, 1}}},
                  {boxes = boxes})
end

-- "clusters": n spheres in 64 clusters, each a cube of side 3 to 7 so dense
-- that its spheres overlap many times over.
function M.clusters(n)
  local u, K, centres = lcg(11), 64, {}
  for c = 1, K do
    local spread = 1.5 + 2 * u()
    centres[c] = {-40 + 80 * u(), spread + 1 + 4 * u(), -40 + 80 * u(), spread}
  end
  local function spheres(emit)
    for k = 0, n - 1 do
      local c = centres[k % K + 1]
      local x = c[1] + c[4] * (2 * u() - 1)
      local y = c[2] + c[4] * (2 * u() - 1)
      local z = c[3] + c[4] * (2 * u() - 1)
      emit(x, y, z, 0.15 + 0.35 * u(), "p" .. (k % 8))
    end
  end
  return open_air("clusters", {eye = {0, 30, 75}, target = {0, 2, 0}, up = {0, 1, 0},
                               hfov = 60},
                  {{position = {40, 60, 30}, color = {1, 1, 1}}}, {spheres = spheres})
end

-- "mixed": n objects scattered on the ground, by turns a sphere, a box, an
-- open cylinder, a leaning quad and a triangle.
function M.mixed(n)
  local u = lcg(13)
  local list, boxes, cylinders, quads, triangles = {}, {}, {}, {}, {}
  for k = 0, n - 1 do
    local x, z, s = -50 + 100 * u(), -50 + 100 * u(), 0.15 + 0.4 * u()
    local m, kind = "p" .. (k % 8), k % 5
    if kind == 0 then
      list[#list + 1] = {x, s, z, s, m}
    elseif kind == 1 then
      boxes[#boxes + 1] = {min = {x - s, 0, z - s}, max = {x + s, 1.5 * s, z + s},
                           material = m}
    elseif kind == 2 then
      cylinders[#cylinders + 1] = {base = {x, 0, z}, top = {x, 2.5 * s, z},
                                   radius = 0.6 * s, material = m}
    elseif kind == 3 then
      quads[#quads + 1] = {corner = {x - s, 0, z}, u = {2 * s, 0, 0}, v = {0, 2 * s, s},
                           material = m}
    else
      triangles[#triangles + 1] = {a = {x - s, 0, z}, b = {x + s, 0, z},
                                   c = {x, 2 * s, z + 0.3 * s}, material = m}
    end
  end
  return open_air("mixed", {eye = {0, 12, 62}, target = {0, 0, 0}, up = {0, 1, 0},
                            hfov = 60},
                  {{position = {40, 60, 30}, color = {1, 1, 1}}},
                  {spheres = list_emitter(list), boxes = boxes, cylinders = cylinders,
                   quads = quads, triangles = triangles})
end

-- A torus of seg x seg / 2 quads (two triangles each) around +y, major
-- radius 1, minor 0.35: flat lists, faces 1-based.
local function torus_mesh(seg)
  local vertices, faces, ring = {}, {}, seg // 2
  for i = 0, seg - 1 do
    local a = 2 * math.pi * i / seg
    for j = 0, ring - 1 do
      local b = 2 * math.pi * j / ring
      local r = 1 + 0.35 * cos(b)
      local n = #vertices
      vertices[n + 1], vertices[n + 2], vertices[n + 3] = r * cos(a), 0.35 * sin(b),
                                                          r * sin(a)
    end
  end
  for i = 0, seg - 1 do
    for j = 0, ring - 1 do
      local v00 = i * ring + j + 1
      local v10 = (i + 1) % seg * ring + j + 1
      local v01 = i * ring + (j + 1) % ring + 1
      local v11 = (i + 1) % seg * ring + (j + 1) % ring + 1
      local n = #faces
      faces[n + 1], faces[n + 2], faces[n + 3] = v00, v10, v11
      faces[n + 4], faces[n + 5], faces[n + 6] = v00, v11, v01
    end
  end
  return vertices, faces
end

-- "instances": one torus mesh of 1024 triangles placed g x g times, each
-- turned about y and tilted about x, scaled and set on the ground.
function M.instances(g)
  local u = lcg(17)
  local vertices, faces = torus_mesh(32)
  local placements = {}
  for i = 0, g - 1 do
    for j = 0, g - 1 do
      local a, b = 2 * math.pi * u(), 0.5 * math.pi * u()
      local s = 0.6 + 0.6 * u()
      local x = (i - g / 2 + 0.5) * 4 + u() - 0.5
      local z = (j - g / 2 + 0.5) * 4 + u() - 0.5
      local ca, sa, cb, sb = cos(a), sin(a), cos(b), sin(b)
      -- s * Ry(a) * Rx(b), then up to y = 1.4 s
      placements[#placements + 1] = {
        {s * ca, s * sa * sb, s * sa * cb, x},
        {0, s * cb, -s * sb, 1.4 * s},
        {-s * sa, s * ca * sb, s * ca * cb, z}}
    end
  end
  return open_air("instances", {eye = {0, 1.2 * g, 2.6 * g}, target = {0, 0, 0},
                                up = {0, 1, 0}, hfov = 60},
                  {{position = {2 * g, 3 * g, 1.5 * g}, color = {1, 1, 1}}},
                  {instances = {vertices = vertices, faces = faces, material = "p2",
                                placements = placements}})
end

-- "glass": after Whitted's 1980 picture, a glass sphere (ior 1.5) and a
-- mirror sphere over a checker floor, one light, a uniform background;
-- 5 bounces. The glass is the seed's fixed kr and kt (no Fresnel, kr + kt =
-- 1, so a total internal reflection sends all of it back in both
-- renderers); why not Fresnel is in scenes/bench/glass.lua, lancer's
-- version. The floor is half-way through a layer of the checker's cubes.
function M.glass()
  local function m(c, ka, kd, ks, n, kr)
    return {color = c, ka = ka, kd = kd, ks = ks, n = n, kr = kr}
  end
  local glass = m({1, 1, 1}, 0, 0, 0, 0, 0.1)
  glass.kt, glass.ior = 0.9, 1.5
  local floor = m(nil, 0.1, 0.8, 0, 0, 0)
  floor.checker = {a = {0.95, 0.85, 0.1}, b = {0.9, 0.1, 0.05}, scale = 1}
  return {
    name = "glass",
    camera = {eye = {0, 1.7, -6.5}, target = {0, 0.5, 0}, up = {0, 1, 0}, hfov = 55},
    width = M.WIDTH, height = M.HEIGHT, depth = 5, background = {0.3, 0.5, 0.85},
    lights = {{position = {-4, 7, -5}, color = {1, 1, 1}}},
    materials = {floor = floor, mirror = m({1, 1, 1}, 0, 0, 0, 0, 0.9), glass = glass},
    planes = {{point = {0, -0.5, 0}, normal = {0, 1, 0}, material = "floor"}},
    boxes = {},
    spheres = list_emitter{{-0.7, 0.52, -1.0, 1.0, "glass"},
                           {1.6, 0.62, 1.2, 1.1, "mirror"}},
  }
end

-- The grid's vertex (i, j), 0-based: x_i = -50 + 100 i/Q, z_j likewise.
function M.grid_vertex(mesh, i, j)
  local x = -50 + 100 * i / mesh.q
  local z = -50 + 100 * j / mesh.q
  return x, mesh.height(x, z), z
end

return M
