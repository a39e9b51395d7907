-- test_gallery.lua: every scene and example script runs, in this process, at a
-- tiny size, writes its PNG (05_frames: its 8 frames), and every image it
-- renders is free of NaN and infinite pixels.
local T = require "harness"
local lancer = require "lancer"

local function list_scripts()
  local scripts = {}
  local p = assert(io.popen("ls scenes/seed/*.lua scenes/*.lua examples/*.lua 2>/dev/null"))
  for line in p:lines() do scripts[#scripts + 1] = line end
  p:close()
  return scripts
end

local function exists(path)
  local f = io.open(path, "rb")
  if f then f:close() end
  return f ~= nil
end

-- The table render is looked up in: the binding keeps Scene methods in the
-- metatable's `methods` field (its __index is a function that serves the
-- settable fields); accept a plain __index table too.
local function scene_methods()
  local mt = debug.getregistry()["lancer.Scene"]
  assert(type(mt) == "table", "no lancer.Scene metatable in the registry")
  if type(mt.__index) == "table" then return mt.__index end
  assert(type(mt.methods) == "table", "lancer.Scene has no method table")
  return mt.methods
end

-- Runs script with arg[1] = out, tiny overrides, and every render checked.
-- Returns the number of renders. Restores overrides, render, arg and print.
local function run_script(script, out)
  local methods = scene_methods()
  local render = methods.render
  local renders = 0
  local saved_overrides, saved_arg, saved_print = lancer.overrides, arg, print
  methods.render = function(self, ...)
    local img, stats = render(self, ...)
    renders = renders + 1
    T.eq(img.width, 48, "width under overrides")
    T.eq(img.height, 36, "height under overrides")
    T.eq(T.bad_pixels(img), 0, script .. ": NaN/inf channels in render " .. renders)
    return img, stats
  end
  lancer.overrides = {width = 48, height = 36, samples = 1}
  arg = {[0] = script, [1] = out}
  print = function() end              -- scripts report what they wrote; not here
  local ok, err = pcall(function()
    local chunk = assert(loadfile(script))
    chunk(out)
  end)
  methods.render = render
  lancer.overrides = saved_overrides
  arg = saved_arg
  print = saved_print
  if not ok then error(err, 0) end
  return renders
end

local function shell_quote(s) return "'" .. s:gsub("'", [['\'']]) .. "'" end

for _, script in ipairs(list_scripts()) do
  T.test(script, function()
    local tmp = os.tmpname()
    os.remove(tmp)
    if script:match("05_frames%.lua$") then
      local ok, renders = pcall(run_script, script, tmp) -- tmp: a folder it creates
      local missing = {}
      for i = 1, 8 do
        local path = ("%s/frame_%04d.png"):format(tmp, i)
        if exists(path) then os.remove(path) else missing[#missing + 1] = path end
      end
      os.execute("rmdir " .. shell_quote(tmp) .. " 2>/dev/null")
      if not ok then error(renders, 0) end
      T.eq(#missing, 0, "missing frames: " .. table.concat(missing, ", "))
      T.eq(renders, 8, "renders")
    else
      tmp = tmp .. ".png"
      local ok, renders = pcall(run_script, script, tmp)
      local written = exists(tmp)
      os.remove(tmp)
      if not ok then error(renders, 0) end
      assert(renders >= 1, script .. " rendered nothing")
      assert(written, script .. " did not write " .. tmp)
    end
  end)
end

T.test("gallery: every seed figure has a scene", function()
  local have = {}
  for _, s in ipairs(list_scripts()) do have[s] = true end
  for _, n in ipairs{1, 2, 3, 7, 8, 9, 10, 11, 12, 13, 14} do
    local path = ("scenes/seed/fig%02d.lua"):format(n)
    assert(have[path], path .. " is missing")
  end
end)
