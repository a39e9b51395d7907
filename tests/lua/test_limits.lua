-- test_limits.lua: what the address space cannot hold fails cleanly. The
-- lancer command runs under `ulimit -v 400000` (400 MB of address space)
-- scripts that ask for more: an image, a render, a mesh and a scene too
-- large for it. Each must stop with lancer's "out of memory" naming what it
-- was building, exit 1 (an error, never a kill by a signal), and leave no
-- partial result: nothing printed after the failing call, no file saved.
-- A sanitized build reserves terabytes of shadow memory and cannot start
-- under such a limit: skipped there.
local T = require "harness"

local q = T.quote
local LIMIT_KB = 400000

-- name = {script, the message's words (a Lua pattern), as the test shows them}
local CASES = {
  image = {[[
local lancer = require "lancer"
local img = lancer.image{width = 16000, height = 16000}   -- 3 GB of floats
print("built")
img:save("image.png")
]], "out of memory for a 16000x16000 image", "out of memory for a 16000x16000 image"},
  render = {[[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 0, -4}, at = {0, 0, 0}}}
s:add(lancer.sphere{center = {0, 0, 0}, radius = 1},
      lancer.point_light{position = {0, 2, -4}, intensity = 10})
local img = s:render{width = 16000, height = 16000}
print("built")
img:save("render.png")
]], "out of memory for a 16000x16000 image", "out of memory for a 16000x16000 image"},
  -- Grown piece by piece, as a script builds a large mesh: 24 bytes a
  -- vertex, so the 400 MB run out near 8 million.
  mesh = {[[
local lancer = require "lancer"
local m = lancer.mesh{}
local chunk = {}
for i = 1, 3 * 100000 do chunk[i] = i % 7 end
for _ = 1, 1000 do m:add_vertices(chunk) end
print("built", m)
]], "out of memory: mesh of %d+ vertices", "out of memory: mesh of N vertices"},
  -- A million spheres a call: the scene's shape list outgrows the limit.
  scene = {[[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 0, -4}, at = {0, 0, 0}}}
local ball = lancer.sphere{center = {0, 0, 0}, radius = 1}
local list = {}
for i = 1, 1000000 do list[i] = ball end
for _ = 1, 100 do s:add(list) end
print("built", s)
s:render{width = 4, height = 4}:save("scene.png")
]], "out of memory adding a shape", "out of memory adding a shape"},
}

local function sanitized()
  return os.execute("ldd " .. q(T.lancer) .. " 2>/dev/null | grep -q libasan") == true
end

-- Runs every case at once (they take a second or two each), once.
local results
local function run_all()
  if results then return results end
  local dir = T.temp_dir()
  local names = {}
  for name, case in pairs(CASES) do
    names[#names + 1] = name
    T.write(dir .. "/" .. name .. ".lua", case[1])
  end
  local lancer = io.popen("readlink -f " .. q(T.lancer)):read("l")
  local sh = {"cd " .. q(dir)}
  for _, name in ipairs(names) do
    sh[#sh + 1] = ("(sh -c 'ulimit -v %d && exec \"$0\" \"$1\"' %s %s.lua >%s.out 2>%s.err; " ..
                   "echo $? >%s.code) &"):format(LIMIT_KB, q(lancer), name, name, name, name)
  end
  sh[#sh + 1] = "wait"
  assert(os.execute(table.concat(sh, "\n")), "cannot run the cases in " .. dir)
  results = {}
  for _, name in ipairs(names) do
    local base = dir .. "/" .. name
    results[name] = {out = T.slurp(base .. ".out") or "", err = T.slurp(base .. ".err") or "",
                     code = tonumber(T.slurp(base .. ".code")),
                     saved = T.slurp(base .. ".png") ~= nil}
  end
  os.execute("rm -rf " .. q(dir))
  return results
end

for _, name in ipairs{"image", "render", "mesh", "scene"} do
  local pattern, shown = CASES[name][2], CASES[name][3]
  T.test(("ulimit -v %d: a too-large %s fails with '%s', exit 1, nothing built"):format(
           LIMIT_KB, name, shown), function()
    if sanitized() then T.skip("a sanitized lancer cannot start under ulimit -v") end
    if not os.execute(("sh -c 'ulimit -v %d' 2>/dev/null"):format(LIMIT_KB)) then
      T.skip("this shell has no ulimit -v")
    end
    local r = run_all()[name]
    if r.code ~= 1 then
      error(("exit %s, expected 1 (%s)\nstdout: %s\nstderr: %s"):format(tostring(r.code),
            r.code and r.code > 128 and "killed by signal " .. (r.code - 128) or "no error",
            r.out, r.err), 0)
    end
    assert(r.err:find(pattern), ("%q not in stderr:\n%s"):format(pattern, r.err))
    assert(r.err:find("^lancer: " .. name .. "%.lua:%d+: "),
           "the message does not name the script's line:\n" .. r.err)
    T.eq(r.out, "", "stdout (nothing may run past the failing call)")
    assert(not r.saved, name .. ".png was written")
  end)
end
