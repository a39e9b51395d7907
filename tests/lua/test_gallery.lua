-- test_gallery.lua: every scene and example script runs, in this process, at a
-- tiny size, writes its PNG (05_frames: its 8 frames; animations: their
-- first 2), and every image it
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

local run_script = T.run_script

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
    elseif T.slurp(script):find("lancer.animate", 1, true) then
      -- An animation: its first two frames, through lancer.animate.
      local ok, renders = pcall(run_script, script, tmp .. "_%04d.png", {{1, 2, 1}})
      local missing = {}
      for i = 1, 2 do
        local path = ("%s_%04d.png"):format(tmp, i)
        if exists(path) then os.remove(path) else missing[#missing + 1] = path end
      end
      if not ok then error(renders, 0) end
      T.eq(#missing, 0, "missing frames: " .. table.concat(missing, ", "))
      T.eq(renders, 2, "renders")
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
