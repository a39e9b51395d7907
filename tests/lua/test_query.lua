-- test_query.lua: scene:intersect and scene:occluded from Lua, one ray or
-- flat arrays; mesh uvs and OBJ vt; bad rays; scripts that close the scene
-- from inside the reads.
local T = require "harness"
local lancer = require "lancer"

local HERE = "test_query.lua:"

local function ball_scene()
  local s = lancer.scene{}
  s:add(lancer.sphere{center = {0, 0, 0}, radius = 1},
        lancer.plane{point = {0, -1, 0}, normal = {0, 1, 0}})
  return s
end

T.test("intersect: one ray, its hit against the closed form", function()
  local s = ball_scene()
  local h = s:intersect{origin = {0, 0, 5}, direction = {0, 0, -2}}
  T.eq(h.t, 2, "t in lengths of the direction")
  T.eq(h.point[3], 1, "point")
  T.eq(h.normal[3], 1, "normal")
  T.eq(h.uv[1], 0.5, "u faces +z")
  T.eq(h.uv[2], 0.5, "v on the equator")
  T.eq(h.id, 1, "id")
  T.eq(h.kind, "sphere", "kind")
  T.eq(h.face, nil, "no face on a shape")
  T.eq(s:intersect{origin = {0, 0, 5}, direction = {0, 1, 0}}, nil, "a miss")
  local far = s:intersect{origin = {0, 0, 5}, direction = {0, 0, -1}, tmin = 4.5}
  T.eq(far.t, 6, "tmin starts inside: the far side")
  T.eq(s:intersect{origin = {0, 0, 5}, direction = {0, 0, -1}, tmax = 3.5}, nil, "tmax")
  local floor = s:intersect{origin = {3, 0, 2}, direction = {0, -1, 0}}
  T.eq(floor.kind, "plane", "the floor")
  T.eq(floor.id, 2, "its id")
  T.eq(floor.uv[1], 3, "floor u = x")
  T.eq(floor.uv[2], -2, "floor v = -z")
  T.eq(s:occluded{origin = {0, 0, 5}, direction = {0, 0, -1}}, true, "occluded")
  T.eq(s:occluded{origin = {0, 0, 5}, direction = {0, 0, -1}, tmax = 3.9}, false,
       "stops short")
end)

T.test("intersect: flat arrays, every field, and occluded agrees", function()
  local s = ball_scene()
  local o, d = {}, {}
  for i = 1, 1000 do                        -- more than one chunk into the core
    local a = 2 * math.pi * i / 1000
    table.move({3 * math.cos(a), 0.3, 3 * math.sin(a)}, 1, 3, #o + 1, o)
    table.move({-math.cos(a), 0, -math.sin(a)}, 1, 3, #d + 1, d)
  end
  table.move({0, 5, 0, 0, 0, 0}, 1, 6, #o + 1, o)     -- straight up: a miss ...
  table.move({0, 1, 0, 0, -1, 0}, 1, 6, #d + 1, d)    -- ... and straight down
  local r = s:intersect{origins = o, directions = d}
  local b = s:occluded{origins = o, directions = d}
  T.eq(r.count, 1002, "count")
  T.eq(#r.hit, 1002, "hit")
  T.eq(#r.points, 3 * 1002, "points")
  T.eq(#r.uvs, 2 * 1002, "uvs")
  for i = 1, 1000 do
    assert(r.hit[i] and b[i], "ring ray " .. i)
    T.near(r.t[i], 3 - math.sqrt(1 - 0.09), 1e-14, "t " .. i)
    T.near(r.points[3 * i - 1], 0.3, 1e-15, "y " .. i)
    T.near(r.uvs[2 * i], 0.5 + math.asin(0.3) / math.pi, 1e-14, "v " .. i)
    T.eq(r.ids[i], 1, "id " .. i)
  end
  T.eq(r.hit[1001], false, "the miss")
  T.eq(r.t[1001], math.huge, "its t")
  T.eq(r.ids[1001], 0, "its id")
  T.eq(b[1001], false, "not occluded")
  T.eq(r.hit[1002], true, "down from the centre")
  T.eq(r.t[1002], 1, "meets the inside of the ball")
  local empty = s:intersect{origins = {}, directions = {}}
  T.eq(empty.count, 0, "no rays")
end)

T.test("intersect: bad rays and bad requests are named", function()
  local s = ball_scene()
  local function bad(req, ...)
    T.check_error(function() s:intersect(req) end, HERE, "'intersect'", ...)
    T.check_error(function() s:occluded(req) end, HERE, "'occluded'", ...)
  end
  bad({origin = {0, 0, 0}}, "field 'direction'")
  bad({origin = {0, 0, 0}, direction = {0, 0, 0}}, "direction must not be zero-length")
  bad({origin = {0, 0, 1e31}, direction = {0, 0, 1}}, "origin must be within")
  bad({origin = {0, 0, 0}, direction = {0, 0, 1}, tmin = 1, tmax = 1}, "0 <= tmin < tmax")
  bad({origin = {0, 0, 0}, direction = {0, 0, 1}, origins = {}}, "not both")
  bad({}, "got neither")
  bad({origins = {0, 0, 0, 1}, directions = {0, 0, 1}}, "multiple of 3")
  bad({origins = {0, 0, 0}, directions = {0, 0, 1, 0, 0, 1}}, "2 directions for 1 origins")
  bad({origins = {0, 0, "x"}, directions = {0, 0, 1}}, "entry 3: number expected")
  local o, d = {}, {}
  for i = 1, 600 do
    table.move({0, 0, 5}, 1, 3, #o + 1, o)
    table.move({0, 0, i == 555 and 0 or -1}, 1, 3, #d + 1, d)
  end
  bad({origins = o, directions = d}, "ray 555: direction must not be zero-length")
  bad({origin = {0, 0, 0}, direction = {0, 0, 1}, tmax = "far"}, "field 'tmax'")
  bad({origin = {0, 0, 0}, direction = {0, 0, 1}, tmaxx = 1}, "tmaxx")
end)

T.test("intersect: a script that closes the scene while its rays are read", function()
  local s = ball_scene()
  local o = setmetatable({}, {__len = function() return 3 end,
                              __index = function() getmetatable(s).__close(s); return 0 end})
  T.check_error(function() s:intersect{origins = o, directions = {0, 0, 1}} end,
                "already freed")
end)

T.test("meshes: uvs nested and flat, interpolated at a hit; counts checked", function()
  local s = lancer.scene{}
  local m = lancer.mesh{vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}},
                        faces = {{1, 2, 3, 4}}, uvs = {{0, 0}, {2, 0}, {2, 2}, {0, 2}}}
  s:add(m)
  local h = s:intersect{origin = {0.75, 0.25, -1}, direction = {0, 0, 1}}
  T.eq(h.kind, "mesh", "kind")
  T.eq(h.face, 1, "first face")
  T.near(h.uv[1], 1.5, 1e-15, "u")
  T.near(h.uv[2], 0.5, 1e-15, "v")
  local f = lancer.mesh{vertices = {0, 0, 0, 1, 0, 0, 0, 1, 0}, faces = {1, 2, 3}}
  f:add_uvs{0.5, 0.5, 1, 0.5, 0.5, 1}
  local s2 = lancer.scene{}
  s2:add(f)
  h = s2:intersect{origin = {0.25, 0.25, -1}, direction = {0, 0, 1}}
  -- weights 1/2, 1/4, 1/4 of (0.5, 0.5), (1, 0.5), (0.5, 1)
  T.near(h.uv[1], 0.625, 1e-15, "flat u")
  T.near(h.uv[2], 0.625, 1e-15, "flat v")
  T.check_error(function() lancer.mesh{uvs = {0, 0, 1}} end, HERE, "field 'uvs'",
                "multiple of 2")
  T.check_error(function() lancer.mesh{uvs = {{0, 0 / 0}}} end, HERE, "field 'uvs'",
                "uv 1: {u, v} of 2 finite numbers")
  local short = lancer.mesh{vertices = {0, 0, 0, 1, 0, 0, 0, 1, 0}, faces = {1, 2, 3},
                            uvs = {0, 0}}
  T.check_error(function() lancer.scene{}:add(short) end, HERE, "'add'",
                "1 uvs for 3 vertices")
end)

T.test("load_obj: vt read, vertices split where corners differ, uvs at hits", function()
  local path = os.tmpname() .. ".obj"
  T.write(path, [[
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vt 0.5 0.5 0
f 1/1 2/2 3/3
f 1/5 3/3 4/4
]])
  local m = lancer.load_obj(path)
  os.remove(path)
  T.eq(m.vertex_count, 5, "vertex 1 split: two vt")
  local s = lancer.scene{}
  s:add(m)
  local h = s:intersect{origin = {0.75, 0.25, -1}, direction = {0, 0, 1}}
  T.near(h.uv[1], 0.75, 1e-15, "first face u")
  T.near(h.uv[2], 0.25, 1e-15, "first face v")
  h = s:intersect{origin = {0.25, 0.75, -1}, direction = {0, 0, 1}}
  -- corners (0,0)->vt(0.5,0.5), (1,1)->(1,1), (0,1)->(0,1); weights 1/4, 1/4, 1/2
  T.near(h.uv[1], 0.25 * 0.5 + 0.25 * 1 + 0.5 * 0, 1e-15, "second face u")
  T.near(h.uv[2], 0.25 * 0.5 + 0.25 * 1 + 0.5 * 1, 1e-15, "second face v")
  local bad = os.tmpname() .. ".obj"
  T.write(bad, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n")
  local name = bad:match("[^/]+$")
  T.check_error(function() lancer.load_obj(bad) end, HERE, "'load_obj'",
                name .. ":5: texture index out of range ('2/2')")
  T.write(bad, "v 0 0 0\nvt 0\n")
  T.check_error(function() lancer.load_obj(bad) end, name .. ":2: 'vt' needs 2 finite numbers")
  os.remove(bad)
end)
