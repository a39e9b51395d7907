-- test_safety.lua: scripts that close a scene, mesh or image from inside a
-- metamethod lancer calls while it works on that object (an __index or
-- __len on an options table or a list, a __tostring, the host hook's
-- plain, a finalizer), and lists that change under scene:add. Each must
-- end in a clean error or a correct result, never a crash or a read of
-- freed memory: run them under ASan too (make SAN=1 BUILD=build/san, then
-- lua5.4 with libasan preloaded and LUA_CPATH='build/san/?.so;;').
local T = require "harness"
local lancer = require "lancer"

local HERE = "test_safety.lua:"

-- Closes obj as a script can from anywhere: a <close> variable's end.
local function close(obj)
  local x <close> = obj
end

-- A table that closes obj at the first read of a field it lacks.
local function closing(obj, fields)
  return setmetatable(fields or {}, {__index = function() close(obj) end})
end

-- A list of n elements whose reads (# and [i]) close obj first, each
-- element what make(i) returns.
local function closing_list(obj, n, make)
  return setmetatable({}, {
    __len = function() close(obj) return n end,
    __index = function(_, i) close(obj) return make(i) end})
end

-- A vector {x, y, z} whose reads close obj first.
local function closing_vec(obj, x, y, z)
  local v = {x, y, z}
  return closing_list(obj, 3, function(i) return v[i] end)
end

local function lit_scene()
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}}}
  s:add(lancer.sphere{center = {0, 0, 0}, radius = 3},
        lancer.point_light{position = {0, 5, 5}, intensity = 10})
  return s
end

local function sphere() return lancer.sphere{center = {0, 0, 0}, radius = 1} end

local function triangle()
  return lancer.triangle{a = {0, 0, 0}, b = {1, 0, 0}, c = {0, 1, 0}}
end

-- Runs f with the host hook set to hook, then restores the one before.
local function with_hook(hook, f)
  local old = lancer.set_host_hook(hook)
  local ok, err = pcall(f)
  lancer.set_host_hook(old)
  if not ok then error(err, 0) end
end

local freed = "lancer.Scene already freed"

-- ---- building scenes -------------------------------------------------------

T.test("transformed: the offset's __len and __index close the scene", function()
  local s = lit_scene()
  T.check_error(function() s:transformed(2, closing_vec(s, 1, 2, 3)) end,
                HERE, "'transformed'", freed)
end)

T.test("add: a list whose reads close the scene", function()
  local s = lit_scene()
  T.check_error(function() s:add(closing_list(s, 2, sphere)) end, HERE, "'add'", freed)
end)

T.test("add: a list whose reads close a mesh in it; the scene stays as it was",
       function()
  local s = lit_scene()
  local m = triangle()
  local list = setmetatable({m}, {__len = function() return 2 end,
                                  __index = function() close(m) return sphere() end})
  T.check_error(function() s:add(list) end, HERE, "'add'", "lancer.Mesh already freed")
  T.eq(#s:objects(), 2, "objects after the failed add")
end)

T.test("add: an element that turns into the list itself is read once", function()
  local s = lancer.scene{}
  local reads, list = 0, nil
  list = setmetatable({}, {__len = function() return 1 end, __index = function()
    reads = reads + 1
    if reads == 1 then return sphere() end
    return list                       -- a second read would recurse for ever
  end})
  s:add(list)
  T.eq(reads, 1, "reads of the element")
  T.eq(s:count(), 1, "shapes")
end)

T.test("add: a list holding itself, and groups nested too deep, are refused", function()
  local s = lancer.scene{}
  local l = {sphere()}
  l[2] = l
  T.check_error(function() s:add(l) end, HERE, "'add'", "element 2:",
                "lists and groups nest at most 64 deep")
  local g = lancer.group{sphere()}
  for _ = 1, 70 do g = lancer.group{g} end
  T.check_error(function() s:add(g) end, HERE, "'add'",
                "lists and groups nest at most 64 deep")
  T.eq(s:count(), 0, "shapes after the failed adds")
  local ok = lancer.group{sphere()}
  for _ = 1, 60 do ok = lancer.group{ok} end
  s:add(ok)
  T.eq(s:count(), 1, "a group 61 deep")
end)

T.test("scene.background and scene.ambient: a colour whose reads close the scene",
       function()
  local s = lit_scene()
  T.check_error(function() s.background = closing_vec(s, 0.5, 0.5, 0.5) end,
                HERE, "scene.background", freed)
  local s2 = lit_scene()
  T.check_error(function() s2.ambient = closing_vec(s2, 0.1, 0.1, 0.1) end,
                HERE, "scene.ambient", freed)
end)

T.test("scene.camera: a freed scene is refused", function()
  local s = lit_scene()
  close(s)
  local cam = lancer.camera{from = {0, 0, 1}, at = {0, 0, 0}}
  T.check_error(function() s.camera = cam end, HERE, freed)
end)

-- ---- render and explain ----------------------------------------------------

T.test("render: the options' __index closes the scene", function()
  local s = lit_scene()
  T.check_error(function() s:render(closing(s, {width = 4, height = 4})) end,
                HERE, "'render'", freed)
end)

T.test("render: the host hook's plain, given options that close the scene", function()
  local s = lit_scene()
  with_hook(function(_, plain, self, opts)
    return plain(self, closing(self, {width = 4, height = 4}))
  end, function()
    T.check_error(function() s:render{width = 4, height = 4} end, freed)
  end)
end)

T.test("render: the host hook closes the scene, then calls plain", function()
  local s = lit_scene()
  with_hook(function(_, plain, self, opts)
    close(self)
    return plain(self, opts)
  end, function()
    T.check_error(function() s:render{width = 4, height = 4} end, freed)
  end)
end)

T.test("explain: the options' __index closes the scene", function()
  local s = lit_scene()
  T.check_error(function()
    s:explain(closing(s, {x = 1, y = 1, width = 4, height = 4}))
  end, HERE, "'explain'", freed)
end)

T.test("explain: the host hook's plain, given options that close the scene", function()
  local s = lit_scene()
  with_hook(function(_, plain, self, opts)
    return plain(self, closing(self, {x = 1, y = 1, width = 4, height = 4}))
  end, function()
    T.check_error(function() s:explain{x = 1, y = 1, width = 4, height = 4} end, freed)
  end)
end)

-- ---- listing and removing --------------------------------------------------

T.test("remove: the entry's __index closes the scene", function()
  local s = lit_scene()
  T.check_error(function()
    s:remove(setmetatable({}, {__index = function() close(s) return 1 end}))
  end, HERE, "'remove'", freed)
end)

T.test("remove: a shape's __tostring closes the scene", function()
  local s = lit_scene()
  local sp = sphere()
  s:add(sp)
  local mt = getmetatable(sp)
  local saved = mt.__tostring
  mt.__tostring = function() close(s) return "the sphere" end
  local ok, err = pcall(function() s:remove(sp) end)
  mt.__tostring = saved
  assert(not ok, "no error raised")
  T.has(err, freed)
end)

T.test("objects: entries outlive their scene; a freed scene is refused", function()
  local s = lit_scene()
  local list = s:objects()
  close(s)
  T.eq(#list, 2, "entries")
  T.has(tostring(list[2]), "#2 lancer.point_light{")
  T.check_error(function() s:objects() end, HERE, "'objects'", freed)
end)

-- ---- meshes ----------------------------------------------------------------

local mesh_freed = "lancer.Mesh already freed"

T.test("mesh:add_vertices: a nested point list whose reads close the mesh", function()
  local m = triangle()
  T.check_error(function()
    m:add_vertices(closing_list(m, 2, function() return {1, 1, 1} end))
  end, HERE, mesh_freed)
end)

T.test("mesh:add_vertices: a flat list whose reads close the mesh", function()
  local m = triangle()
  T.check_error(function()
    m:add_vertices(closing_list(m, 3, function(i) return i end))
  end, HERE, mesh_freed)
end)

T.test("mesh:add_vertices: a point whose reads close the mesh", function()
  local m = triangle()
  T.check_error(function() m:add_vertices{closing_vec(m, 1, 2, 3)} end, HERE, mesh_freed)
end)

T.test("mesh:add_normals: a list whose reads close the mesh", function()
  local m = triangle()
  T.check_error(function()
    m:add_normals(closing_list(m, 3, function() return {0, 0, 1} end))
  end, HERE, mesh_freed)
end)

T.test("mesh:add_faces: nested and flat lists whose reads close the mesh", function()
  local m = triangle()
  T.check_error(function()
    m:add_faces(closing_list(m, 1, function() return {1, 2, 3} end))
  end, HERE, mesh_freed)
  local m2 = triangle()
  T.check_error(function()
    m2:add_faces(closing_list(m2, 3, function(i) return i end))
  end, HERE, mesh_freed)
  local m3 = triangle()
  T.check_error(function()
    m3:add_faces{closing_list(m3, 3, function(i) return i end)}
  end, HERE, mesh_freed)
end)

-- ---- images ----------------------------------------------------------------

local image_freed = "lancer.Image already freed"

T.test("img:save: the options' __index closes the image", function()
  local img = lancer.image{width = 2, height = 2}
  local path = os.tmpname() .. ".png"
  T.check_error(function() img:save(path, closing(img)) end, HERE, "'save'", image_freed)
  T.eq(io.open(path), nil, "a file written")
end)

T.test("img:save: the host hook's plain, given options that close the image", function()
  local img = lancer.image{width = 2, height = 2}
  local path = os.tmpname() .. ".png"
  with_hook(function(_, plain, self, p)
    return plain(self, p, closing(self))
  end, function()
    T.check_error(function() img:save(path) end, image_freed)
  end)
  T.eq(io.open(path), nil, "a file written")
end)

-- ---- finalizers ------------------------------------------------------------

-- A finalizer runs at whatever allocation the collector picks, often
-- inside the binding's own (a userdata for the image, a table for the
-- statistics). Garbage whose __gc closes the objects, made before each
-- call with a different amount of other garbage after it, strikes the
-- methods at many points over the runs; each call must end in a result
-- or a clean error.
T.test("finalizers that close the scene, mesh or image strike mid-method", function()
  local calls = {
    function(s) return s:render{width = 2, height = 2} end,
    function(s) return s:explain{x = 1, y = 1, width = 2, height = 2} end,
    function(s) return s:transformed(2, {1, 2, 3}) end,
    function(s) return s:add({sphere(), lancer.point_light{position = {0, 1, 0}}}) end,
    function(s) return s:add(lancer.sphere{center = {0, 0, 0}, radius = 1,
                                           material = lancer.material{}}) end,
    function(s) return s:objects() end,
    function(s) return s:remove(1) end,
    function(s) s.background = {0.1, 0.2, 0.3} end,
    function(s, m) return s:add(m:moved(lancer.translate(1, 0, 0)), m) end,
    function(_, m) return m:add_vertices{{1, 1, 1}, {2, 2, 2}} end,
    function(_, m) return m:add_faces{{1, 2, 3}} end,
    function(_, _, img) return img:save(os.tmpname() .. ".png") end,
    function(_, _, img) return img:add(img) end,
  }
  local struck = {}                     -- per call: finalizers run inside it
  local inside
  -- Generational, a minor collection at each 1 % of growth: each runs the
  -- finalizers of the garbage made since the last.
  local mode = collectgarbage("generational", 1, 100)
  local ok, err = pcall(function()
    for run = 1, 40 do
      for c, call in ipairs(calls) do
        local s, m, img = lit_scene(), triangle(), lancer.image{width = 2, height = 2}
        setmetatable({}, {__gc = function()     -- garbage, finalized soon
          if inside then struck[inside] = (struck[inside] or 0) + 1 end
          close(s) close(m) close(img)
        end})
        for k = 1, run do local _ = {k} end   -- a different phase each run
        inside = c
        local done, why = pcall(call, s, m, img)
        inside = nil
        if not done then
          why = tostring(why)
          assert(why:find("already freed", 1, true), why)
        end
      end
    end
  end)
  collectgarbage("generational", 20, 100)       -- lua5.4's defaults
  if mode == "incremental" then collectgarbage("incremental") end
  assert(ok, err)
  local total = 0
  for _, n in pairs(struck) do total = total + n end
  assert(total > 0, "no finalizer ran inside a method: the test tests nothing")
end)
