-- test_sandbox_walk.lua: under lancer --sandbox, no function a scene can
-- reach opens a path outside the allowed folders. A script walks every
-- function of lancer and lancer.core (and of the modules beside them, and
-- the methods of the objects it can make) and calls each with a probe path
-- outside both folders in each argument position, as a string, as a
-- table's field path and as a list's item: whatever mentions the path must
-- be the sandbox's refusal, never a format error or the file's content, and
-- the refusal must read the same for a path that is missing.
local T = require "harness"

local q = T.quote

local function output_of(cmd)
  local p = assert(io.popen(cmd))
  local s = p:read("a")
  p:close()
  return s
end

local ROOT = output_of("pwd"):gsub("\n$", "")
local LANCER = T.lancer:sub(1, 1) == "/" and T.lancer or ROOT .. "/" .. T.lancer
local SECRET = "probe-secret-5b2e"

-- Runs in the sandbox: arg[1] the folder outside, arg[2] the secret. Prints
-- "@@BAD name: why" for each leak, "@@REFUSED name" for each function that
-- refused the probe, "@@COUNT n" for the functions called.
local WALKER = [==[
local lancer = require "lancer"
local core = require "lancer.core"
local OUTSIDE, SECRET = arg[1], arg[2]
local EXTS = {"png", "hdr", "exr", "obj", "txt"}

local funcs, names = {}, {}       -- function -> {name, make (self) or nil}
local function add(name, f, make)
  if type(f) == "function" and not funcs[f] then
    funcs[f] = {name = name, make = make}
    names[#names + 1] = f
  end
end

local seen = {}
local function walk(t, prefix)
  if seen[t] then return end
  seen[t] = true
  local keys = {}
  for k in pairs(t) do keys[#keys + 1] = tostring(k) end
  table.sort(keys)
  for _, k in ipairs(keys) do
    local v = rawget(t, k)
    if type(v) == "function" then add(prefix .. "." .. k, v)
    elseif type(v) == "table" then walk(v, prefix .. "." .. k) end
  end
  local mt = getmetatable(t)
  if type(mt) == "table" and type(mt.__index) == "table" then walk(mt.__index, prefix) end
end
walk(lancer, "lancer")
walk(core, "lancer.core")
for _, m in ipairs{"lancer.motion", "lancer.anim", "lancer.ledger"} do
  walk(require(m), m)
end

-- The objects a scene can make, each made afresh for every call; their
-- metatables' functions and methods are called with the object as self.
local function cam() return lancer.camera{from = {0, 0, -3}, at = {0, 0, 0}} end
local function small_scene()
  local s = lancer.scene{camera = cam()}
  s:add(lancer.sphere{center = {0, 0, 0}, radius = 1},
        lancer.point_light{position = {0, 2, -2}, intensity = 5})
  return s
end
local makers = {
  Image = function() return lancer.image{width = 2, height = 2} end,
  Scene = small_scene,
  Mesh = function() return lancer.load_obj("scene/tri.obj") end,
  Texture = function() return lancer.checker{} end,
  Material = function() return lancer.material{} end,
  Light = function() return lancer.point_light{position = {0, 1, 0}, intensity = 1} end,
  Camera = cam,
  Sphere = function() return lancer.sphere{center = {0, 0, 0}, radius = 1} end,
  Csg = function()
    return lancer.union{lancer.sphere{center = {0, 0, 0}, radius = 1},
                        lancer.box{min = {0, 0, 0}, max = {1, 1, 1}}}
  end,
  Entry = function() return small_scene():objects()[1] end,
  RayTree = function() return small_scene():explain{x = 1, y = 1, width = 4, height = 4} end,
}
local mts = {}
local function add_methods(kind, make)
  local ok, obj = pcall(make)
  if not ok then print("@@BAD " .. kind .. ": cannot make one: " .. tostring(obj)) return end
  local mt = getmetatable(obj)
  if type(mt) ~= "table" or mts[mt] then return end
  mts[mt] = true
  local function from(t)
    for k, v in pairs(t) do
      if type(v) == "function" and k ~= "__gc" and k ~= "__close" and k ~= "__index"
         and k ~= "__newindex" then
        add(kind .. ":" .. tostring(k), v, make)
      end
    end
  end
  from(mt)
  if type(mt.methods) == "table" then from(mt.methods) end
  if type(mt.__index) == "table" then from(mt.__index) end
end
local kinds = {}
for kind in pairs(makers) do kinds[#kinds + 1] = kind end
table.sort(kinds)
for _, kind in ipairs(kinds) do add_methods(kind, makers[kind]) end

-- The argument lists: the path (p) as a string, {path = p} or {p} at
-- position 1 to 3, the others nil or a path allowed to be written.
local FILL = "out/fill.png"
local function arglists(p)
  local lists = {}
  for pos = 1, 3 do
    for _, shape in ipairs{"string", "field", "list"} do
      for _, fill in ipairs{false, FILL} do
        local a = {n = 3}
        for i = 1, 3 do a[i] = fill or nil end
        a[pos] = shape == "string" and p or shape == "field" and {path = p} or {p}
        lists[#lists + 1] = a
      end
    end
  end
  return lists
end

-- What a call told: the error, or the sentence after a nil (io.open's way);
-- and whether any result holds the secret.
local function call(f, make, a)
  local self = make and make()
  local r = table.pack(pcall(function()
    if make then return f(self, table.unpack(a, 1, a.n)) end
    return f(table.unpack(a, 1, a.n))
  end))
  local told
  if not r[1] then told = tostring(r[2])
  elseif r[2] == nil or r[2] == false then told = r[3] ~= nil and tostring(r[3]) or nil end
  local leaked = false
  for i = 2, r.n do
    if type(r[i]) == "string" and r[i]:find(SECRET, 1, true) then leaked = true end
  end
  return told, leaked
end

local function refused_msg(msg, p)
  return msg:find("sandbox: not reading '" .. p .. "'", 1, true) or
         msg:find("sandbox: not writing '" .. p .. "'", 1, true)
end
local function plain(s) return (s:gsub("[%p]", "%%%0")) end

-- Whether msg names the path p, beyond echoing it as a wrong value: raised
-- as it was given (lancer.anim.usage) or quoted as "got '...'" (an option's
-- or an axis's check). A loader's or writer's message names it otherwise.
local function mentions(msg, p)
  if msg == p then return false end
  return (msg:gsub(plain("got '" .. p .. "'"), "")):find(p, 1, true) ~= nil
end

local count = 0
for _, f in ipairs(names) do
  local info = funcs[f]
  count = count + 1
  local refused = false
  for _, ext in ipairs(EXTS) do
    local probe = OUTSIDE .. "/probe." .. ext
    local missing = OUTSIDE .. "/missing." .. ext
    local lists, mlists = arglists(probe), arglists(missing)
    for i, a in ipairs(lists) do
      local told, leaked = call(f, info.make, a)
      if leaked then print("@@BAD " .. info.name .. ": returned the probe's content") end
      if told and told:find(SECRET, 1, true) then
        print("@@BAD " .. info.name .. ": told the probe's content: " .. told)
      elseif told and mentions(told, probe) then
        if not refused_msg(told, probe) then
          print("@@BAD " .. info.name .. ": not the sandbox's refusal: " .. told)
        else
          refused = true
          local mtold = call(f, info.make, mlists[i]) or "(nothing)"
          local a1 = told:gsub(plain(probe), "PATH")
          local a2 = mtold:gsub(plain(missing), "PATH")
          if a1 ~= a2 then
            print("@@BAD " .. info.name .. ": a missing file tells otherwise: '" ..
                  a1 .. "' against '" .. a2 .. "'")
          end
        end
      end
    end
  end
  if refused then print("@@REFUSED " .. info.name) end
end
print("@@COUNT " .. count)
]==]

local function exists(path)
  return os.execute("test -e " .. q(path) .. " -o -L " .. q(path)) == true
end

local function have(cmd) return os.execute("command -v " .. cmd .. " >/dev/null 2>&1") end

T.test("sandbox: no reachable function opens a path outside the folders", function()
  local dir = T.temp_dir()
  assert(os.execute(("cd %s && mkdir scene out outside"):format(q(dir))))
  local outside = output_of("cd " .. q(dir .. "/outside") .. " && pwd -P"):gsub("\n$", "")
  for _, ext in ipairs{"png", "hdr", "exr", "obj", "txt"} do
    T.write(outside .. "/probe." .. ext, SECRET .. "\n")
  end
  T.write(dir .. "/scene/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
  T.write(dir .. "/scene/walk.lua", WALKER)
  -- strace, where there is one, sees what the process opened, whatever it said;
  -- not on a sanitized build, whose LeakSanitizer cannot run under ptrace.
  local sanitized = os.execute(("nm %s 2>/dev/null | grep -q __asan_"):format(
    q((LANCER:gsub("/bin/lancer$", "")) .. "/liblancer.a")))
  local trace = have("strace") and not sanitized and
    ("strace -f -o %s -e trace=open,openat,creat," ..
    "rename,renameat,renameat2,unlink,unlinkat,truncate,mkdir,mkdirat,execve "):format(
    q(dir .. "/trace")) or ""
  local o, e, code = T.run(("cd %s && %s%s --sandbox --sandbox-out out " ..
    "--max-seconds 120 scene/walk.lua %s %s < /dev/null"):format(
    q(dir), trace, q(LANCER), q(outside), q(SECRET)))
  T.check_exit(code, 0, o, e)
  local bad = {}
  for line in o:gmatch("@@BAD ([^\n]*)") do bad[#bad + 1] = line end
  assert(#bad == 0, "reachable unchecked:\n" .. table.concat(bad, "\n"))
  local refused = {}
  for name in o:gmatch("@@REFUSED (%S+)") do refused[name] = true end
  -- The walk reached the known readers and writers (else it proves nothing).
  for _, name in ipairs{"lancer.load_obj", "lancer.load_png", "lancer.load_exr",
                        "lancer.load_hdr", "lancer.merge_tiles", "lancer.image_texture",
                        "Image:save"} do
    assert(refused[name], name .. " was not refused:\n" .. o)
  end
  local count = tonumber(o:match("@@COUNT (%d+)"))
  assert(count and count > 60, "the walk called only " .. tostring(count) .. " functions")
  for _, ext in ipairs{"png", "hdr", "exr", "obj", "txt"} do
    T.eq(T.slurp(outside .. "/probe." .. ext), SECRET .. "\n", "probe." .. ext)
  end
  T.eq(output_of("ls -A " .. q(outside)), "probe.exr\nprobe.hdr\nprobe.obj\nprobe.png\n" ..
       "probe.txt\n", "the folder outside")
  if trace ~= "" then
    local opened = {}
    for line in T.slurp(dir .. "/trace"):gmatch("[^\n]+") do
      if line:find(outside .. "/", 1, true) then opened[#opened + 1] = line end
    end
    assert(#opened == 0, "opened outside the folders:\n" .. table.concat(opened, "\n"))
  end
  assert(not exists(dir .. "/scene/pwned"))
  os.execute("rm -rf " .. q(dir))
end)
