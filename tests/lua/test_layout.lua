-- test_layout.lua: the checklist atop src/shapes/shape.c says what a new kind of
-- shape touches; this reads the places it names and fails when a primitive
-- kind of src/shapes/shape.h (PRIM_*) is missing from one that applies to it, so a
-- kind added in some of them and forgotten in others is caught here, not by
-- a render that silently skips it.
local T = require "harness"

local function read(path)
  return assert(T.slurp(path), path .. ": cannot be read (run from the repository root)")
end

-- C source without its comments, so a name only mentioned in prose counts
-- for nothing.
local function code(path)
  return (read(path):gsub("/%*.-%*/", " "))
end

-- The text of a definition in C source: a function or a table named at the
-- start of a line, from its name to its matching closing brace (a
-- declaration, ended by ';' before any '{', is passed over).
local function body(src, name, path)
  local at = 1
  while true do
    local s, e = src:find("\n[%w_ %*]-[ %*]" .. name .. "%s*[%(%[]", at)
    assert(s, ("%s: no definition of %s"):format(path, name))
    local open, semi = src:find("{", e, true), src:find(";", e, true)
    if open and (not semi or open < semi) then
      local block = src:match("%b{}", open)
      assert(block, ("%s: %s has no end"):format(path, name))
      return src:sub(s, open - 1) .. block
    end
    at = e + 1
  end
end

local function has(text, plain) return text:find(plain, 1, true) ~= nil end

-- The kinds, in shape.h's order: every PRIM_* before PRIM_KINDS.
local SHAPE_H = code("src/shapes/shape.h")
local function prim_ids()
  local enum = assert(SHAPE_H:match("enum%s*{%s*(PRIM_SPHERE.-)PRIM_KINDS%s*}"),
                      "src/shapes/shape.h: no enum of PRIM_* ids ending in PRIM_KINDS")
  local ids = {}
  for name in enum:gmatch("PRIM_([%u%d_]+)") do ids[#ids + 1] = name end
  return ids
end

-- Shape kinds among them: shape.c's prim_kinds table maps LC_X to PRIM_X.
local SHAPE_C = code("src/shapes/shape.c")
local function shape_kinds()
  local kinds = {}
  for lc, prim in body(SHAPE_C, "prim_kinds", "src/shapes/shape.c"):gmatch(
      "%[LC_([%u%d_]+)%]%s*=%s*PRIM_([%u%d_]+)") do
    assert(lc == prim, ("src/shapes/shape.c: prim_kinds maps LC_%s to PRIM_%s"):format(lc, prim))
    kinds[prim] = true
  end
  return kinds
end

-- Every place checked below, by file: the checklist must name each one.
local PLACES = {"src/lancer.h", "src/shapes/shape.h", "src/shapes/shape.c",
                "src/scene/intersect.c", "src/lua/lua_shapes.c", "src/scene/csg.c",
                "src/scene/csg.h", "docs/manual.md"}

T.test("shape.c's checklist names every place this test checks", function()
  local top = assert(read("src/shapes/shape.c"):match("^/%*(.-)%*/"), "src/shapes/shape.c: no top comment")
  local named = {}
  for path in top:gmatch("(%a+/[%w_/]+%.%a+)") do named[path] = true end
  for _, path in ipairs(PLACES) do
    assert(named[path], "src/shapes/shape.c's checklist does not name " .. path)
  end
  for path in pairs(named) do
    if not path:find("wedge") and path ~= "tests/lua/test_layout.lua" then
      assert(T.slurp(path), "src/shapes/shape.c's checklist names a missing file: " .. path)
    end
  end
end)

T.test("the kind field of a primitive id has room for every kind", function()
  local ids = prim_ids()
  local bits = tonumber(SHAPE_H:match("#define%s+PRIM_KIND_BITS%s+(%d+)"))
  assert(bits, "src/shapes/shape.h: no PRIM_KIND_BITS")
  -- Kinds 0 .. #ids - 1; the all-ones kind is PRIM_NONE, never a primitive's.
  assert(#ids <= (1 << bits) - 1,
         ("%d kinds do not fit %d bits besides PRIM_NONE"):format(#ids, bits))
  local shift = tonumber(read("src/accel/bvh.h"):match("#define%s+BVH_KIND_SHIFT%s+(%d+)"))
  T.eq(shift, 32 - bits, "src/accel/bvh.h's BVH_KIND_SHIFT against 32 - PRIM_KIND_BITS")
end)

T.test("every primitive kind has a BVH cost and its cases in intersect.c", function()
  local cost = body(SHAPE_C, "shape_prim_cost", "src/shapes/shape.c")
  local intersect = code("src/scene/intersect.c")
  local missing = {}
  for _, x in ipairs(prim_ids()) do
    if not has(cost, "[PRIM_" .. x .. "]") then
      missing[#missing + 1] = "src/shapes/shape.c shape_prim_cost: PRIM_" .. x
    end
    if not intersect:find("PRIM_" .. x .. "%f[^%w_]") then
      missing[#missing + 1] = "src/scene/intersect.c: PRIM_" .. x
    end
  end
  assert(#missing == 0, "missing:\n  " .. table.concat(missing, "\n  "))
end)

-- What one shape kind x (PRIM_X, LC_X) must have in each place; the list
-- of what is missing.
local function check_kind(X, missing)
  local x = X:lower()
  local function need(ok, where, what)
    if not ok then missing[#missing + 1] = ("%s: %s (%s)"):format(where, what, x) end
  end
  local LC = "LC_" .. X
  -- 1. lancer.h: in lc_shape_kind, before LC_SHAPE_KINDS.
  local lancer = code("src/lancer.h")
  local enum = lancer:match("typedef%s+enum%s*{([^}]-LC_SHAPE_KINDS)[^}]*}%s*lc_shape_kind")
  need(enum and enum:find(LC .. "%f[^%w_]"), "src/lancer.h", LC .. " in lc_shape_kind")
  -- 2, 3. Its own files.
  local own_h = T.slurp("src/shapes/" .. x .. ".h")
  need(T.slurp("src/shapes/" .. x .. ".c"), "src/shapes/" .. x .. ".c", "the file")
  need(own_h, "src/shapes/" .. x .. ".h", "the file")
  own_h = own_h and own_h:gsub("/%*.-%*/", " ") or ""
  local placed = has(own_h, '#include "placed.h"')
  for _, f in ipairs{"_check", "_prepare", "_uv"} do
    need(has(own_h, x .. f .. "("), "src/shapes/" .. x .. ".h", x .. f)
  end
  -- 5. shape.c: the tables and the switches.
  local function in_body(name, plain, what)
    need(has(body(SHAPE_C, name, "src/shapes/shape.c"), plain), "src/shapes/shape.c " .. name, what or plain)
  end
  in_body("kind_names", "[" .. LC .. "] = \"" .. x .. "\"")
  in_body("geom_sizes", "[" .. LC .. "]")
  in_body("lc_shape_check", x .. "_check(")
  in_body("shape_prepare", x .. "_prepare(")
  in_body("shape_uv", x .. "_uv(")
  local bounded = not has(body(SHAPE_C, "shape_bounded", "src/shapes/shape.c"), LC)
  local emits = not has(body(SHAPE_C, "shape_can_emit", "src/shapes/shape.c"), LC)
  if bounded then in_body("shape_bounds", x .. "_bounds(") end
  if emits then in_body("shape_light_sample", x .. "_light_sample(") end
  local stored = body(SHAPE_C, "lc_shape_stored", "src/shapes/shape.c")
  need(has(stored, (placed and "placed" or x) .. "_geom"), "src/shapes/shape.c lc_shape_stored",
       "its geometry in the union")
  if placed then
    local lo, hi = body(SHAPE_C, "placed_kind", "src/shapes/shape.c"):match(
      "k%s*>=%s*LC_([%u%d_]+)%s*&&%s*k%s*<=%s*LC_([%u%d_]+)")
    local order = {}
    for name in enum:gmatch("LC_([%u%d_]+)") do order[#order + 1] = name end
    local at = {}
    for i, name in ipairs(order) do at[name] = i end
    need(lo and at[lo] <= at[X] and at[X] <= at[hi], "src/shapes/shape.c placed_kind", LC)
    if emits then in_body("shape_prepare_emitter", x .. "_area(") end
  else
    in_body("lc_shape_transform", x .. "_transform(")
    in_body("shape_describe", x .. "_describe(")
    in_body("shape_scale", x .. "_scale(")
    if emits then
      in_body("shape_light_centre", x .. "_light_centre(")
      in_body("shape_light_begin", x .. "_light_begin(")
    end
  end
  -- 6. intersect.c: the nearest-hit switch.
  local intersect = code("src/scene/intersect.c")
  local prim_t = body(intersect, "prim_t", "src/scene/intersect.c")
  need(has(prim_t, "case PRIM_" .. X .. ":"), "src/scene/intersect.c prim_t", "case PRIM_" .. X)
  need(prim_t:find(x .. "_t%(") or prim_t:find(x .. "_hit"), "src/scene/intersect.c prim_t",
       "its distance test")
  local finish = body(intersect, "prim_finish", "src/scene/intersect.c")
  local complete = intersect:match("#define%s+COMPLETE%s+(%b())") or ""
  need(has(finish, "PRIM_" .. X) or has(complete, "PRIM_" .. X),
       "src/scene/intersect.c prim_finish", "PRIM_" .. X .. " (or its bit in COMPLETE)")
  -- 7. lua_shapes.c: fields, constructor, registration.
  local lua = code("src/lua/lua_shapes.c")
  need(has(body(lua, "kind_fields", "src/lua/lua_shapes.c"), "[" .. LC .. "]"),
       "src/lua/lua_shapes.c kind_fields", LC)
  need(lua:find("\nstatic int w_" .. x .. "%("), "src/lua/lua_shapes.c", "w_" .. x)
  need(has(body(lua, "lb_shapes_register", "src/lua/lua_shapes.c"),
           "{\"" .. x .. "\", w_" .. x .. "}"), "src/lua/lua_shapes.c lb_shapes_register", x)
  -- 8. csg.c and csg.h, for the kinds that bound a solid.
  local csg = code("src/scene/csg.c")
  if has(body(csg, "closed_kind", "src/scene/csg.c"), LC) then
    need(has(body(csg, "shape_cross", "src/scene/csg.c"), x .. "_hit"),
         "src/scene/csg.c shape_cross", x .. "_hit")
    local leaf = code("src/scene/csg.h"):match("union%s*(%b{})%s*g;") or ""
    need(has(leaf, (placed and "placed" or x) .. "_geom"), "src/scene/csg.h csg_leaf",
         "its geometry in the union")
  end
  -- 9. The manual: its constructor and its texture coordinates.
  local manual = read("docs/manual.md")
  need(has(manual, "`lancer." .. x .. "{"), "docs/manual.md", "lancer." .. x .. "{...}")
  local uv = manual:match("\n### Texture coordinates\n(.-)\n###") or ""
  local row = false
  for cell in uv:gmatch("\n| ([^|]-) |") do
    if (" " .. cell:gsub(",", " ") .. " "):find(" " .. x .. " ", 1, true) then row = true end
  end
  need(row, "docs/manual.md Texture coordinates", "its row")
end

T.test("every shape kind is in every place shape.c's checklist names", function()
  local kinds, missing, n = shape_kinds(), {}, 0
  for _, X in ipairs(prim_ids()) do
    if kinds[X] then
      n = n + 1
      check_kind(X, missing)
    end
  end
  assert(n >= 9, ("only %d shape kinds found in src/shapes/shape.c's prim_kinds"):format(n))
  assert(#missing == 0, "missing:\n  " .. table.concat(missing, "\n  "))
end)
