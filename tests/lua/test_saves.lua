-- test_saves.lua: the lancer command never leaves half a file behind: a
-- save killed by SIGTERM or SIGHUP removes its temporary, and past ulimit -f
-- the save fails with an error instead of the process dying.
local T = require "harness"

local function temporaries(dir)
  local p = assert(io.popen("ls -a " .. T.quote(dir)))
  local n = 0
  for name in p:lines() do
    if name:find(".tmp-", 1, true) then n = n + 1 end
  end
  p:close()
  return n
end

local SAVER = [[
local lancer = require "lancer"
local img = lancer.image{width = 3000, height = 3000, color = {0.2, 0.4, 0.6}}
for y = 1, 3000, 7 do for x = 1, 3000, 5 do img:set(x, y, x / 3000, y / 3000, 0.5) end end
while true do img:save(arg[1]) end
]]

for _, sig in ipairs{"TERM", "HUP"} do
  T.test("a save killed by SIG" .. sig .. " leaves no temporary", function()
    local dir = T.temp_dir()
    T.write(dir .. "/saver.lua", SAVER)
    local pidfile = dir .. "/pid"
    os.execute(("%s %s %s >/dev/null 2>&1 & echo $! > %s"):format(T.lancer,
      T.quote(dir .. "/saver.lua"), T.quote(dir .. "/frame.png"), T.quote(pidfile)))
    local pid = T.slurp(pidfile):match("%d+")
    local seen = false
    for _ = 1, 1000 do                  -- up to 10 s for a save to be under way
      if temporaries(dir) > 0 then seen = true break end
      os.execute("sleep 0.01")
    end
    os.execute("kill -" .. sig .. " " .. pid .. "; sleep 0.3")
    local left = temporaries(dir)
    os.execute("kill -9 " .. pid .. " 2>/dev/null; rm -rf " .. T.quote(dir))
    assert(seen, "no save was under way")
    T.eq(left, 0, "temporaries left")
  end)
end

T.test("past ulimit -f a save fails with an error, not SIGXFSZ", function()
  local dir = T.temp_dir()
  T.write(dir .. "/big.lua", [[
local lancer = require "lancer"
local img = lancer.image{width = 2000, height = 2000}
for y = 1, 2000, 3 do for x = 1, 2000, 3 do img:set(x, y, x / 2000, y / 2000, 0.5) end end
img:save(arg[1])
]])
  local out, err, code = T.run(("sh -c 'ulimit -f 100; exec %s %s %s'"):format(T.lancer,
    T.quote(dir .. "/big.lua"), T.quote(dir .. "/big.png")))
  local left = temporaries(dir)
  os.execute("rm -rf " .. T.quote(dir))
  T.check_exit(code, 1, out, err)
  T.has(err, "File too large", "stderr")
  T.eq(left, 0, "temporaries left")
end)
