-- test_layers.lua: the core's layout, read off the built objects with nm:
-- no circle of calls between core files (data flows one way: render ->
-- shade -> intersect -> shapes, as README.md's folders do), and no core
-- file calls Lua, prints or exits (the binding and the command do that).
local T = require "harness"

local OBJ = (T.lancer:match("^(.*)/bin/[^/]*$") or "build") .. "/obj"

-- The core's objects, as "folder/name": every one but the binding's
-- (obj/lua/) and the command's (obj/cli/), and the MINIMAL build's shading.
local function core_objects()
  local list = {}
  local p = assert(io.popen("ls " .. T.quote(OBJ) .. "/*/*.o"))
  for path in p:lines() do
    local folder, name = path:match("([^/]+)/([^/]+)%.o$")
    if folder ~= "lua" and folder ~= "cli" and name ~= "shade_minimal" then
      list[#list + 1] = folder .. "/" .. name
    end
  end
  p:close()
  return list
end

-- name -> {defines = {sym = true}, uses = {sym = true}}
local function symbols(objects)
  local out = {}
  for _, name in ipairs(objects) do
    local s = {defines = {}, uses = {}}
    local p = assert(io.popen("nm " .. T.quote(OBJ .. "/" .. name .. ".o")))
    for line in p:lines() do
      local kind, sym = line:match("^%x+ (%a) (%S+)$")
      if kind and kind:match("[TDBR]") then s.defines[sym] = true end
      local u = line:match("^%s+U (%S+)$")
      if u then s.uses[u] = true end
    end
    p:close()
    out[name] = s
  end
  return out
end

local function calls(objects, syms)
  local owner = {}
  for name, s in pairs(syms) do
    for sym in pairs(s.defines) do owner[sym] = name end
  end
  local edges = {}
  for name, s in pairs(syms) do
    edges[name] = {}
    for sym in pairs(s.uses) do
      local o = owner[sym]
      if o and o ~= name then edges[name][o] = sym end
    end
  end
  return edges
end

T.test("layers: no circle of calls between core files", function()
  local objects = core_objects()
  assert(#objects > 10, "too few core objects in " .. OBJ)
  local edges = calls(objects, symbols(objects))
  local state, path = {}, {}
  local function visit(v)
    state[v] = "open"
    path[#path + 1] = v
    local targets = {}
    for w in pairs(edges[v]) do targets[#targets + 1] = w end
    table.sort(targets)
    for _, w in ipairs(targets) do
      if state[w] == "open" then
        local i = #path
        while path[i] ~= w do i = i - 1 end
        local cycle = {table.unpack(path, i)}
        cycle[#cycle + 1] = w
        error("a circle of calls: " .. table.concat(cycle, ".c -> ") .. ".c (" ..
              edges[v][w] .. ")", 0)
      elseif not state[w] then
        visit(w)
      end
    end
    path[#path] = nil
    state[v] = "done"
  end
  table.sort(objects)
  for _, v in ipairs(objects) do
    if not state[v] then visit(v) end
  end
end)

T.test("layers: the core calls no Lua, prints nothing and never exits", function()
  local objects = core_objects()
  assert(#objects > 10, "too few core objects in " .. OBJ)
  local syms = symbols(objects)
  local banned = {"printf", "fprintf", "vfprintf", "puts", "fputs", "putchar", "fputc",
                  "perror", "exit", "_exit", "abort", "__printf_chk", "__fprintf_chk"}
  for _, name in ipairs(objects) do
    for sym in pairs(syms[name].uses) do
      assert(not sym:match("^lua") and not sym:match("^luaL_"),
             name .. ".c calls Lua (" .. sym .. ")")
      for _, b in ipairs(banned) do
        assert(sym ~= b, name .. ".c calls " .. b)
      end
    end
  end
end)

-- The core's folders in the Makefile's order (CORE_DIRS; test_folders.lua
-- holds it to README.md's): a call may go to an object of its own folder or
-- of one listed before it, as includes do. Public functions (lc_*) that a
-- lower folder would call are no exception: an include test cannot see
-- those, since every folder includes lancer.h.
T.test("layers: no core folder calls into one listed after it", function()
  local dirs = assert(T.slurp("Makefile"):match("\nCORE_DIRS%s*:=%s*([^\n]*)"),
                      "Makefile: no CORE_DIRS")
  local rank, n = {}, 0
  for d in dirs:gmatch("%S+") do n = n + 1; rank[d] = n end
  local objects = core_objects()
  assert(#objects > 10, "too few core objects in " .. OBJ)
  local edges = calls(objects, symbols(objects))
  local bad = {}
  for from, targets in pairs(edges) do
    for to, sym in pairs(targets) do
      local a, b = from:match("^[^/]+"), to:match("^[^/]+")
      assert(rank[a] and rank[b], ("%s or %s is in no folder of CORE_DIRS"):format(from, to))
      if rank[b] > rank[a] then
        bad[#bad + 1] = ("%s.c calls %s (%s.c): src/%s/ is after src/%s/"):format(
          from, sym, to, b, a)
      end
    end
  end
  table.sort(bad)
  assert(#bad == 0, table.concat(bad, "\n"))
end)
