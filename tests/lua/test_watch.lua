-- test_watch.lua: lancer --watch on a pseudo-terminal (python3's pty
-- module): the first run drawn pass by pass, a redraw within a second of a
-- save of the script, of a file it dofile'd and of one it require'd, a
-- syntax error printed under the picture it leaves alone, Ctrl-C quitting.
local T = require "harness"

local q = T.quote

local function absolute(path)
  local p = assert(io.popen("readlink -f " .. q(path)))
  local abs = p:read("l")
  p:close()
  return abs
end

-- Drives `lancer --watch scene.lua out.png` in the folder argv[2]; prints
-- one "name value" line per measure. Output is read as it comes, each
-- chunk stamped with the time it arrived.
local DRIVER = [==[
import os, pty, select, signal, sys, time
lancer, folder = sys.argv[1], sys.argv[2]
os.chdir(folder)
env = dict(os.environ, TERM="xterm-256color", COLORTERM="truecolor")
env.pop("NO_COLOR", None)
pid, fd = pty.fork()
if pid == 0:
    os.execve(lancer, [lancer, "--watch", "scene.lua", "out.png"], env)
seen = b""
def until(marker, limit):
    """Reads until marker appears in what came since the call; the seconds
    that took, or -1 after limit seconds."""
    global seen
    got, t0 = b"", time.time()
    while time.time() - t0 < limit:
        r, _, _ = select.select([fd], [], [], 0.01)
        if r:
            try:
                d = os.read(fd, 65536)
            except OSError:
                break
            got += d
            if marker in got:
                seen += got
                return time.time() - t0, got
    seen += got
    return -1, got
def save(path, text):
    with open(path + ".new", "w") as f:
        f.write(text)
    os.rename(path + ".new", path)          # as editors save
def report(name, value):
    print(name, value, flush=True)

t, got = until(b"Ctrl-C quits", 20)
report("first", "%.3f" % t)
for k in range(1, 5):
    report("pass%d" % k, int((b"pass %d," % k) in got))
report("clears_first", got.count(b"\x1b[2J"))
png1 = open("out.png", "rb").read() if os.path.exists("out.png") else b""
time.sleep(0.3)

save("color.lua", "return {0.2, 0.9, 0.3}\n")
t, got = until(b"Ctrl-C quits", 5)
report("dofiled", "%.3f" % t)
report("clears_dofiled", got.count(b"\x1b[2J"))
png2 = open("out.png", "rb").read() if os.path.exists("out.png") else b""
report("png_changed", int(png1 != b"" and png2 != b"" and png1 != png2))
time.sleep(0.3)

save("size.lua", "return {width = 40, height = 20}\n")
t, got = until(b"Ctrl-C quits", 5)
report("required", "%.3f" % t)
report("clears_required", got.count(b"\x1b[2J"))
report("status_required", int(b"40x20" in got))
time.sleep(0.3)

good = open("scene.lua").read()
save("scene.lua", good + "\nlocal = 1\n")
t, got = until(b"Ctrl-C quits", 5)
report("broken", "%.3f" % t)
report("clears_broken", got.count(b"\x1b[2J"))
report("error_shown", int(b"scene.lua:" in got and b"near" in got))
time.sleep(0.3)

save("scene.lua", good)
t, got = until(b"Ctrl-C quits", 5)
report("mended", "%.3f" % t)
report("clears_mended", got.count(b"\x1b[2J"))
time.sleep(0.3)

os.write(fd, b"\x03")                        # Ctrl-C, as the terminal sends it
t0, status = time.time(), None
while time.time() - t0 < 5:
    done, st = os.waitpid(pid, os.WNOHANG)
    if done:
        status = st
        break
    try:
        select.select([fd], [], [], 0.05) and os.read(fd, 65536)
    except OSError:
        pass
if status is None:
    os.kill(pid, signal.SIGKILL)
    os.waitpid(pid, 0)
    report("exit", "none")
else:
    report("exit", os.waitstatus_to_exitcode(status))
]==]

local SCENE = [[
local lancer = require "lancer"
local size = require "size"
local color = dofile("color.lua")
local s = lancer.scene{camera = lancer.camera{from = {0, 0, -4}, at = {0, 0, 0}}}
s:add(lancer.sphere{center = {0, 0, 0}, radius = 1,
                    material = lancer.material{color = color}},
      lancer.point_light{position = {2, 4, -3}, intensity = 25})
local img = s:render{width = size.width, height = size.height, samples = 8}
img:save(arg[1])
]]

T.test("--watch: redrawn pass by pass within a second of each save", function()
  if not os.execute("command -v python3 >/dev/null 2>&1") then
    T.skip("python3 is not installed")
  end
  local dir = T.temp_dir()
  T.write(dir .. "/scene.lua", SCENE)
  T.write(dir .. "/color.lua", "return {0.9, 0.2, 0.1}\n")
  T.write(dir .. "/size.lua", "return {width = 32, height = 16}\n")
  T.write(dir .. "/driver.py", DRIVER)
  local out, err, code = T.run(("python3 %s %s %s"):format(q(dir .. "/driver.py"),
                                 q(absolute(T.lancer)), q(dir)))
  os.execute("rm -rf " .. q(dir))
  T.check_exit(code, 0, out, err)
  local r = {}
  for name, value in out:gmatch("(%S+) (%S+)\n") do r[name] = value end
  local function seconds(name)
    local t = tonumber(r[name])
    assert(t and t >= 0, ("%s: no redraw seen (%s)\n%s"):format(name, tostring(r[name]), out))
    return t
  end
  seconds("first")
  for k = 1, 4 do T.eq(r["pass" .. k], "1", ("pass %d of 8 samples drawn"):format(k)) end
  T.eq(r.clears_first, "1", "screen cleared once by the first run's render")
  for _, name in ipairs{"dofiled", "required", "mended"} do
    local t = seconds(name)
    assert(t < 1, ("%s: redrawn %.3f s after the save"):format(name, t))
    T.eq(r["clears_" .. name], "1", name .. ": screen cleared once")
  end
  T.eq(r.png_changed, "1", "out.png rewritten with the new colour")
  T.eq(r.status_required, "1", "the required file's size used")
  assert(seconds("broken") < 1, "the syntax error reported within a second")
  T.eq(r.error_shown, "1", "the syntax error printed")
  T.eq(r.clears_broken, "0", "the picture left on screen after the error")
  T.eq(r.exit, "0", "exit status after Ctrl-C")
end)

T.test("--watch: usage errors", function()
  local cases = {
    {"--watch", "option '--watch' needs a script file to watch"},
    {"--watch -", "option '--watch' needs a script file to watch"},
    {"--watch --check x.lua", "option '--watch' cannot go with --check"},
    {"--watch -i x.lua", "option '--watch' cannot go with -i"},
    {"--watch --frames 1-3 x.lua", "option '--watch' cannot go with --frames"},
  }
  for _, c in ipairs(cases) do
    local out, err, code = T.run(T.lancer .. " " .. c[1] .. " </dev/null")
    T.check_exit(code, 2, out, err)
    T.has(err, c[2])
  end
end)
