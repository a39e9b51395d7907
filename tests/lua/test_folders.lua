-- test_folders.lua: the core's folders depend one way. README.md's "Where
-- things are" lists src/'s folders in their allowed order: a file may
-- include headers of its own folder, of folders listed above its own, and
-- src/lancer.h; never of a folder listed below (which would let two folders
-- include each other). No .c file lies at src/'s top, only the public
-- headers lancer.h and lancer_sandbox.h; the Makefile builds the core's
-- folders in the same order.
local T = require "harness"

-- src/'s folders in README.md's order: the lines "src/NAME/  ..." of its
-- listing under "## Where things are".
local function readme_order()
  local text = T.slurp("README.md")
  local section = assert(text:match("\n## Where things are\n(.-)\n## ") or
                         text:match("\n## Where things are\n(.*)$"),
                         "README.md has no 'Where things are' section")
  local order = {}
  for name in section:gmatch("\n%s*src/([%w_]+)/%s") do order[#order + 1] = name end
  return order
end

local function lines_of(cmd)
  local list, p = {}, assert(io.popen(cmd))
  for line in p:lines() do list[#list + 1] = line end
  p:close()
  return list
end

-- Every violation in files {path = {includes...}} under an order of
-- folders: "path includes folder/name.h (folder is listed after own)".
-- Bare names resolve to the including file's folder, else to src/'s top.
local function violations(order, files, exists)
  local rank = {}
  for i, name in ipairs(order) do rank[name] = i end
  local bad = {}
  for path, includes in pairs(files) do
    local own = path:match("^src/([%w_]+)/[^/]+$")
    for _, inc in ipairs(includes) do
      local folder = inc:match("^([%w_]+)/[^/]+$")
      if not folder then
        if exists(("src/%s/%s"):format(own or "", inc)) then
          folder = own
        elseif not exists("src/" .. inc) then
          bad[#bad + 1] = ("%s includes %s, which is in no folder of src/"):format(path, inc)
        end
      end
      if folder and folder ~= own then
        if not rank[folder] then
          bad[#bad + 1] = ("%s includes %s: src/%s/ is not in README.md's order")
                          :format(path, inc, folder)
        elseif own and rank[own] and rank[folder] > rank[own] then
          bad[#bad + 1] = ("%s includes %s: src/%s/ is listed after src/%s/ in "
                           .. "README.md, so src/%s/ must not know it")
                          :format(path, inc, folder, own, own)
        end
      end
    end
  end
  table.sort(bad)
  return bad
end

local function includes_of(path)
  local list = {}
  for inc in T.slurp(path):gmatch('\n%s*#%s*include%s+"([^"]+)"') do list[#list + 1] = inc end
  return list
end

local function file_exists(path)
  local f = io.open(path)
  if f then f:close() end
  return f ~= nil
end

T.test("README.md lists every folder of src/ and only those", function()
  local order, listed = readme_order(), {}
  assert(#order > 0, "README.md's 'Where things are' names no src/ folder")
  for _, name in ipairs(order) do listed[name] = true end
  local present = {}
  for _, dir in ipairs(lines_of("find src -mindepth 1 -maxdepth 1 -type d | sort")) do
    local name = dir:match("^src/(.+)$")
    present[name] = true
    assert(listed[name], ("src/%s/ is not in README.md's 'Where things are'"):format(name))
  end
  for _, name in ipairs(order) do
    assert(present[name], ("README.md lists src/%s/, which does not exist"):format(name))
  end
end)

T.test("no .c file at src/'s top; only the public headers there", function()
  local top = lines_of("find src -maxdepth 1 -type f | sort")
  T.eq(table.concat(top, " "), "src/lancer.h src/lancer_sandbox.h", "files at src/'s top")
end)

T.test("the Makefile's CORE_DIRS are README.md's core folders, in order", function()
  local dirs = assert(T.slurp("Makefile"):match("\nCORE_DIRS%s*:=%s*([^\n]*)"),
                      "Makefile: no CORE_DIRS")
  local core = {}
  for _, name in ipairs(readme_order()) do
    if name ~= "lua" and name ~= "cli" then core[#core + 1] = name end
  end
  T.eq(dirs:gsub("%s+$", ""):gsub("%s+", " "), table.concat(core, " "),
       "CORE_DIRS against README.md (less lua and cli)")
end)

T.test("every include goes to the file's own folder or one listed before it", function()
  local files = {}
  for _, path in ipairs(lines_of("find src -name '*.[ch]' | sort")) do
    files[path] = includes_of(path)
  end
  local bad = violations(readme_order(), files, file_exists)
  assert(#bad == 0, #bad .. " includes against README.md's order:\n  " ..
         table.concat(bad, "\n  "))
end)

T.test("the order check finds an upward include and two folders that know each other",
       function()
  local exists = function(path) return path == "src/lancer.h" or path == "src/a/x.h" end
  local files = {["src/a/x.c"] = {"x.h", "lancer.h", "b/y.h"},
                 ["src/b/y.c"] = {"a/x.h"}}
  local bad = violations({"a", "b"}, files, exists)
  T.eq(#bad, 1, "violations in a -> b, b -> a")
  T.has(bad[1], "src/a/x.c includes b/y.h", "the violation")
  bad = violations({"a"}, {["src/a/x.c"] = {"c/z.h", "nowhere.h"}}, exists)
  T.eq(#bad, 2, "an unlisted folder and an unknown header")
end)
