-- test_sandbox.lua: lancer --sandbox against the escapes and the caps,
-- through the built command; binary chunks refused outside the sandbox
-- too; --max-memory and --max-seconds; lancer.sandbox; the C API.
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

local function now() return tonumber(output_of("date +%s%N")) / 1e9 end

-- A fresh folder: scene/ (the script's folder, an asset and links out of
-- it), out/ (the output folder, with links out of it) and secret.txt
-- beside them, outside both.
local function layout()
  local dir = T.temp_dir()
  assert(os.execute(("cd %s && mkdir scene scene/sub out && " ..
    "echo 'the secret' > secret.txt && echo 'an asset' > scene/asset.txt && " ..
    "ln -s ../secret.txt scene/link && ln -s .. scene/up && " ..
    "ln -s .. out/escape && ln -s ../made.txt out/dangling"):format(q(dir))))
  return dir
end

-- Writes script as dir/scene/scene.lua and runs `lancer OPTIONS
-- scene/scene.lua` from dir: stdout, stderr, exit status, seconds taken.
local function run(dir, options, script, args)
  if script then T.write(dir .. "/scene/scene.lua", script) end
  local t0 = now()
  local o, e, code = T.run(("cd %s && %s %s scene/scene.lua %s"):format(
    q(dir), q(LANCER), options, args or ""))
  return o, e, code, now() - t0
end

local function exists(path)
  return os.execute("test -e " .. q(path) .. " -o -L " .. q(path)) == true
end

local function cleanup(dir) os.execute("rm -rf " .. q(dir)) end

local function have_timeout()
  return os.execute("command -v timeout >/dev/null 2>&1") == true
end

-- The probe every escape script starts with: one line per attempt,
-- "NAME REFUSED message" or "NAME ALLOWED value".
local PROBE = [[
local lancer = require "lancer"
local function probe(name, f)
  local ok, a, b = pcall(f)
  if ok and a ~= nil then print(name .. " ALLOWED " .. tostring(a))
  else print(name .. " REFUSED " .. tostring(ok and b or a)) end
end
]]

local function lines_of(out)
  local t = {}
  for name, verdict, rest in out:gmatch("(%S+) (%u+) ([^\n]*)") do
    t[name] = {verdict = verdict, msg = rest}
  end
  return t
end

-- Each name must be refused, its message naming what was refused.
local function check_refused(out, expect)
  local got = lines_of(out)
  for name, part in pairs(expect) do
    local g = got[name]
    assert(g, ("%s: no line in:\n%s"):format(name, out))
    assert(g.verdict == "REFUSED", ("%s was allowed: %s"):format(name, g.msg))
    assert(g.msg:find(part, 1, true), ("%s: %q not in %q"):format(name, part, g.msg))
  end
  return got
end

T.test("sandbox: no programs, C code, debug library or string.dump", function()
  local dir = layout()
  local o, e, code = run(dir, "--sandbox", PROBE .. [[
probe("execute", function() return os.execute("touch pwned") end)
probe("popen", function() return io.popen("touch pwned") end)
probe("loadlib", function()
  return package.loadlib(arg[1] .. "/build/lancer/core.so", "luaopen_lancer_core")
end)
probe("cmodule", function()
  package.cpath = arg[1] .. "/build/lancer/?.so"
  return require "core"
end)
probe("searchpath", function() return package.searchpath("x", "./?.lua") end)
probe("debug", function() return debug.getinfo(1) end)
probe("registry", function() return debug.getregistry() end)
probe("dump", function() return string.dump(probe) end)
probe("dumpmethod", function() return ("").dump(probe) end)
probe("exit", function() return os.exit(0) end)
probe("getenv", function() return os.getenv("HOME") end)
probe("tmpname", function() return os.tmpname() end)
probe("tmpfile", function() return io.tmpfile() end)
probe("setlocale", function() return os.setlocale("C") end)
probe("hook", function() return lancer.set_host_hook end)
probe("corehook", function() return require("lancer.core").set_host_hook end)
probe("host", function() return require "lancer.host" end)
probe("package", function() return require "package" end)
probe("debugmod", function() return require "debug" end)
probe("motion", function() return require "lancer.motion" end)
]], q(ROOT))
  T.check_exit(code, 0, o, e)
  local got = check_refused(o, {
    execute = "sandbox: os.execute(\"touch pwned\") is refused",
    popen = "sandbox: io.popen is refused",
    loadlib = "sandbox: package.loadlib is refused",
    cmodule = "sandbox: require 'core' is refused",
    searchpath = "sandbox: package.searchpath is refused",
    debug = "sandbox: debug.getinfo is refused",
    registry = "debug.getregistry is refused",
    dump = "sandbox: string.dump is refused", dumpmethod = "string.dump is refused",
    exit = "sandbox: os.exit is refused", getenv = "sandbox: os.getenv is refused",
    tmpname = "os.tmpname is refused", tmpfile = "io.tmpfile is refused",
    setlocale = "os.setlocale is refused", host = "require 'lancer.host' is refused",
    package = "require 'package' is refused", debugmod = "require 'debug' is refused"})
  T.eq(got.hook.verdict, "REFUSED", "lancer.set_host_hook is gone")
  T.eq(got.corehook.verdict, "REFUSED", "lancer.core.set_host_hook is gone")
  T.eq(got.motion.verdict, "ALLOWED", "require 'lancer.motion'")
  assert(not exists(dir .. "/pwned") and not exists(dir .. "/scene/pwned"),
         "a program ran")
  cleanup(dir)
end)

-- A binary chunk, dumped here (stock lua5.4 has string.dump).
local function write_chunk(path)
  local f = assert(io.open(path, "wb"))
  f:write(string.dump(load("print('bytecode ran', ...)")))
  f:close()
end

T.test("sandbox: binary chunks refused: load, loadfile, dofile, the script", function()
  local dir = layout()
  write_chunk(dir .. "/scene/chunk.luac")
  local o, e, code = run(dir, "--sandbox", PROBE .. [[
local f = assert(io.open("scene/chunk.luac", "rb"))
local bin = f:read("a")
f:close()
probe("load", function() return load(bin) end)
probe("loadb", function() return load(bin, "chunk", "b") end)
probe("loadreader", function()
  local done
  return load(function() if not done then done = true; return bin end end)
end)
probe("loadfile", function() return loadfile("scene/chunk.luac", "b") end)
probe("dofile", function() return dofile("scene/chunk.luac") end)
probe("text", function() return load("return 6 * 7", "t", "b")() end)
]])
  T.check_exit(code, 0, o, e)
  local got = check_refused(o, {load = "sandbox: binary chunks are refused",
    loadb = "sandbox: binary chunks are refused",
    loadreader = "binary chunks are refused",
    loadfile = "sandbox: binary chunks are refused",
    dofile = "binary chunks are refused"})
  T.eq(got.text.msg, "42", "a text chunk loads whatever mode is asked")
  assert(not o:find("bytecode ran", 1, true), "a binary chunk ran:\n" .. o)
  -- The script itself: refused unless --allow-bytecode, which --sandbox refuses.
  write_chunk(dir .. "/scene/scene.lua")
  o, e, code = run(dir, "--sandbox")
  T.check_exit(code, 1, o, e)
  T.has(e, "scene/scene.lua is a binary (precompiled) chunk, refused")
  o, e, code = run(dir, "")
  T.check_exit(code, 1, o, e)
  T.has(e, "lancer: scene/scene.lua is a binary (precompiled) chunk, refused: Lua " ..
           "does not verify them (--allow-bytecode runs it)")
  assert(not o:find("bytecode ran", 1, true), "a binary script ran")
  o, e, code = run(dir, "--allow-bytecode", nil, "x")
  T.check_exit(code, 0, o, e)
  T.has(o, "bytecode ran\tx")
  o, e, code = run(dir, "--sandbox --allow-bytecode")
  T.check_exit(code, 2, o, e)
  T.has(e, "option '--allow-bytecode' cannot go with --sandbox")
  T.eq(o, "", "stdout of a usage error")
  cleanup(dir)
end)

T.test("bytecode: load, loadfile, dofile, require, stdin take text only", function()
  local dir = layout()
  write_chunk(dir .. "/scene/chunk.luac")
  write_chunk(dir .. "/scene/binmod.lua")
  local script = PROBE .. [[
local bin = io.open("scene/chunk.luac", "rb"):read("a")
package.path = "scene/?.lua"
probe("load", function() return load(bin) end)
probe("loadfile", function() return loadfile("scene/chunk.luac") end)
probe("dofile", function() return dofile("scene/chunk.luac") or "ran" end)
probe("require", function() return require "binmod" end)
]]
  local o, e, code = run(dir, "", script)
  T.check_exit(code, 0, o, e)
  check_refused(o, {load = "binary chunks are refused (Lua does not verify them; " ..
                           "lancer --allow-bytecode allows them)",
                    loadfile = "--allow-bytecode allows them",
                    dofile = "scene/chunk.luac: binary chunks are refused",
                    require = "error loading module 'binmod'"})
  assert(not o:find("bytecode ran", 1, true), "a binary chunk ran:\n" .. o)
  o, e, code = run(dir, "--allow-bytecode", script)
  T.check_exit(code, 0, o, e)
  for _, name in ipairs{"load", "loadfile", "dofile", "require"} do
    local got = lines_of(o)[name]
    T.eq(got and got.verdict, "ALLOWED", name .. " with --allow-bytecode")
  end
  o, e, code = T.run(q(LANCER) .. " - < " .. q(dir .. "/scene/chunk.luac"))
  T.check_exit(code, 1, o, e)
  T.has(e, "lancer: stdin is a binary (precompiled) chunk, refused")
  cleanup(dir)
end)

T.test("sandbox: reads only below the script's folder; no .. or link out", function()
  local dir = layout()
  local img = require("lancer").image{width = 2, height = 1}
  img:save(dir .. "/scene/tex.png")
  img:save(dir .. "/tex_outside.png")
  T.write(dir .. "/scene/sub/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
  T.write(dir .. "/scene/sub/helper.lua", "return 'helper ran'\n")
  -- Files the binding opens on its own: an OBJ's library and a library's map.
  T.write(dir .. "/scene/sub/lib.obj", "mtllib /etc/passwd\nv 0 0 0\nv 1 0 0\nv 0 1 0\n" ..
          "usemtl x\nf 1 2 3\n")
  T.write(dir .. "/scene/sub/map.mtl", "newmtl x\nmap_Kd ../../tex_outside.png\n")
  T.write(dir .. "/scene/sub/map.obj", "mtllib map.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n" ..
          "usemtl x\nf 1 2 3\n")
  local o, e, code = run(dir, "--sandbox", PROBE .. [[
probe("passwd", function() return assert(io.open("/etc/passwd")):read("a") end)
probe("passwdopen", function() return io.open("/etc/passwd") end)
probe("passwdobj", function() return lancer.load_obj("/etc/passwd") end)
probe("passwdlines", function() return io.lines("/etc/passwd")() end)
probe("passwdinput", function() return io.input("/etc/passwd") end)
probe("passwddofile", function() return dofile("/etc/passwd") end)
probe("passwdloadfile", function() return loadfile("/etc/passwd") end)
probe("dotdot", function() return io.open("../secret.txt") end)
probe("dotdotdeep", function() return io.open("scene/sub/../../secret.txt") end)
probe("missingdotdot", function() return io.open("scene/nothing/../../secret.txt") end)
probe("link", function() return io.open("scene/link") end)
probe("linkdir", function() return io.open("scene/up/secret.txt") end)
probe("pngout", function() return lancer.load_png("tex_outside.png") end)
probe("pnglink", function() return lancer.load_png("scene/up/tex_outside.png") end)
probe("proc", function() return io.open("/proc/self/environ") end)
probe("asset", function() return assert(io.open("scene/asset.txt")):read("l") end)
probe("obj", function() return lancer.load_obj("scene/sub/tri.obj") end)
probe("png", function() return lancer.load_png("scene/tex.png") end)
probe("helper", function() return dofile("scene/sub/helper.lua") end)
probe("missing", function() return io.open("scene/missing.txt") end)
probe("mtllib", function() return lancer.load_obj("scene/sub/lib.obj") end)
probe("mtlmap", function() return lancer.load_obj("scene/sub/map.obj") end)
probe("texpath", function() return lancer.image_texture{path = "tex_outside.png"} end)
]])
  T.check_exit(code, 0, o, e)
  local folder = output_of("cd " .. q(dir) .. " && pwd -P"):gsub("\n$", "") .. "/scene"
  local outside = "it does not resolve below the scene's folder '" .. folder .. "'"
  local got = check_refused(o, {
    passwd = "sandbox: not reading '/etc/passwd': " .. outside,
    passwdopen = "sandbox: not reading '/etc/passwd'",
    passwdobj = "scene/scene.lua:9: bad argument #1 to 'load_obj' (sandbox: not " ..
                "reading '/etc/passwd'",
    passwdlines = "bad argument #1 to 'lines' (sandbox: not reading",
    passwdinput = "bad argument #1 to 'input' (sandbox: not reading",
    passwddofile = "bad argument #1 to 'dofile' (sandbox: not reading",
    passwdloadfile = "sandbox: not reading '/etc/passwd'",
    dotdot = "not reading '../secret.txt'",
    dotdotdeep = "not reading 'scene/sub/../../secret.txt'",
    missingdotdot = "not reading", link = "not reading 'scene/link'",
    linkdir = "not reading 'scene/up/secret.txt'",
    pngout = "bad argument #1 to 'load_png'",
    pnglink = "not reading 'scene/up/tex_outside.png'",
    proc = "not reading '/proc/self/environ'",
    missing = "scene/missing.txt: No such file or directory",
    mtllib = "bad argument #1 to 'load_obj' (sandbox: not reading '/etc/passwd'",
    mtlmap = "sandbox: not reading 'scene/sub/../../tex_outside.png'",
    texpath = "bad argument #1 to 'image_texture' (sandbox: not reading 'tex_outside.png'"})
  T.eq(got.asset.msg, "an asset", "an asset in the folder")
  T.has(got.obj.msg, "lancer.Mesh (3 vertices, 1 faces)")
  T.has(got.png.msg, "lancer.Image 2x1")
  T.eq(got.helper.msg, "helper ran", "dofile of a helper in the folder")
  assert(not o:find("root:", 1, true) and not o:find("the secret", 1, true),
         "something outside was read:\n" .. o)
  -- From standard input the scene has no folder: it reads nothing.
  o, e, code = T.run(("cd %s && %s --sandbox - < scene/scene.lua"):format(q(dir),
                                                                          q(LANCER)))
  T.check_exit(code, 0, o, e)
  check_refused(o, {asset = "the scene may read no files (it was not read from a file)"})
  cleanup(dir)
end)

T.test("sandbox: writes only below --sandbox-out, none by default; no .. or link out",
       function()
  local dir = layout()
  os.execute("mkdir " .. q(dir .. "/out/frames"))
  local script = PROBE .. [[
local img = lancer.image{width = 2, height = 2}
probe("save", function() return img:save("out/ok.png") end)
probe("write", function()
  local f = io.open("out/ok.txt", "w")
  return f and f:write("written") and f:close()
end)
probe("rename", function() return os.rename("out/ok.txt", "out/moved.txt") end)
probe("read", function() return io.open("out/moved.txt"):read("a") end)
probe("savedotdot", function() return img:save("../x.png") end)
probe("saveup", function() return img:save("out/../x.png") end)
probe("saveabs", function() return img:save(arg[1] .. "/x.png") end)
probe("savelink", function() return img:save("out/escape/x.png") end)
probe("savedangling", function() return img:save("out/dangling") end)
probe("savescene", function() return img:save("scene/x.png") end)
probe("opendotdot", function() return io.open("out/../x.txt", "w") end)
probe("openappend", function() return io.open(arg[1] .. "/secret.txt", "a") end)
probe("openplus", function() return io.open("secret.txt", "r+") end)
probe("opendangling", function() return io.open("out/dangling", "w") end)
probe("openlink", function() return io.open("out/escape/x.txt", "w") end)
probe("output", function() return io.output("x.txt") end)
probe("remove", function() return os.remove("secret.txt") end)
probe("renameout", function() return os.rename("out/moved.txt", "moved.txt") end)
probe("renamein", function() return os.rename("secret.txt", "out/secret.txt") end)
]]
  local o, e, code = run(dir, "--sandbox --sandbox-out out", script, q(dir))
  T.check_exit(code, 0, o, e)
  local out = output_of("cd " .. q(dir .. "/out") .. " && pwd -P"):gsub("\n$", "")
  local outside = "it does not resolve below the output folder '" .. out .. "'"
  local got = check_refused(o, {
    savedotdot = "bad argument #1 to 'save' (sandbox: not writing '../x.png': " ..
                 outside,
    saveup = "not writing 'out/../x.png'", saveabs = "not writing '" .. dir .. "/x.png'",
    savelink = "not writing 'out/escape/x.png'",
    savedangling = "not writing 'out/dangling'",
    savescene = "not writing 'scene/x.png'", opendotdot = "not writing 'out/../x.txt'",
    openappend = "not writing", openplus = "not writing 'secret.txt'",
    opendangling = "not writing 'out/dangling'",
    openlink = "not writing 'out/escape/x.txt'",
    output = "bad argument #1 to 'output' (sandbox: not writing 'x.txt'",
    remove = "not writing 'secret.txt'", renameout = "not writing 'moved.txt'",
    renamein = "not writing 'secret.txt'"})
  T.has(got.savedotdot.msg, "scene/scene.lua:15:", "the refusal's line")
  T.eq(got.save.verdict, "ALLOWED", "img:save below --sandbox-out")
  T.eq(got.read.msg, "written", "a file written, renamed and read back in out/")
  assert(exists(dir .. "/out/ok.png") and exists(dir .. "/out/moved.txt"),
         "nothing written in out/")
  for _, f in ipairs{"x.png", "x.txt", "made.txt", "moved.txt", "scene/x.png",
                     "out/secret.txt"} do
    assert(not exists(dir .. "/" .. f), f .. " was written outside the output folder")
  end
  T.eq(T.slurp(dir .. "/secret.txt"), "the secret\n", "secret.txt, untouched")
  -- With no --sandbox-out nothing is written, anywhere.
  os.execute("rm -f " .. q(dir .. "/out/ok.png") .. " " .. q(dir .. "/out/moved.txt"))
  o, e, code = run(dir, "--sandbox", script, q(dir))
  T.check_exit(code, 0, o, e)
  check_refused(o, {save = "bad argument #1 to 'save' (sandbox: not writing " ..
                           "'out/ok.png': " ..
                           "the scene may write no files (give it a folder with " ..
                           "--sandbox-out DIR))",
                    write = "", rename = "not writing 'out/ok.txt'"})
  assert(not exists(dir .. "/out/ok.png") and not exists(dir .. "/out/ok.txt"),
         "out/ was written")
  cleanup(dir)
end)

T.test("sandbox: animations and --check work; frames only in --sandbox-out", function()
  local dir = layout()
  os.execute("mkdir " .. q(dir .. "/out/frames"))
  local script = [[
local lancer = require "lancer"
lancer.animate{frames = 2, output = arg[1], render = {width = 8, height = 6},
  frame = function(f)
    local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 1, 0}}}
    s:add(lancer.sphere{center = {f.clock, 1, 0}, radius = 1},
          lancer.point_light{position = {2, 4, -3}, intensity = 25})
    return s
  end}
]]
  local sandboxed = "--sandbox --sandbox-out out"
  local o, e, code = run(dir, sandboxed, script, "out/frames/f_%02d.png")
  T.check_exit(code, 0, o, e)
  assert(exists(dir .. "/out/frames/f_01.png") and exists(dir .. "/out/frames/f_02.png"),
         e)
  o, e, code = run(dir, sandboxed .. " --skip-existing", nil, "out/frames/f_%02d.png")
  T.check_exit(code, 0, o, e)
  T.has(e, "frame 2: skipped, out/frames/f_02.png exists")
  -- A folder that is not there is not made: mkdir is a program.
  o, e, code = run(dir, sandboxed, nil, "out/new/f_%02d.png")
  T.check_exit(code, 1, o, e)
  T.has(e, "os.execute(\"mkdir -p 'out/new' 2>/dev/null\") is refused")
  assert(not exists(dir .. "/out/new"), "a folder was made")
  o, e, code = run(dir, sandboxed, nil, "f_%02d.png")
  T.check_exit(code, 1, o, e)
  T.has(e, "frame 1: FAILED: ")
  T.has(e, "bad argument #1 to 'save' (sandbox: not writing 'f_01.png'")
  assert(not exists(dir .. "/f_01.png"), "a frame was written outside")
  o, e, code = run(dir, "--sandbox --check", [[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 1, 0}}}
s:add(lancer.sphere{center = {0, 1, 0}, radius = 1},
      lancer.point_light{position = {2, 4, -3}, intensity = 25})
s:render{width = 16, height = 12}:save("out/never.png")
]])
  T.check_exit(code, 0, o, e)
  T.has(e, "check: 0 of 1 renders unstable")
  cleanup(dir)
end)

T.test("memory cap: a huge Lua table or string fails at once, naming the cap", function()
  local dir = layout()
  local o, e, code, secs = run(dir, "--max-memory 64",
                               "local t = {} for i = 1, 1e9 do t[i] = i end")
  T.check_exit(code, 1, o, e)
  T.has(e, "lancer: not enough memory (lancer's memory cap is 64 MB)")
  assert(secs < 10, ("the cap took %.1f s"):format(secs))
  -- --sandbox's default cap: 1024 MB.
  o, e, code = run(dir, "--sandbox", "local s = string.rep('x', 2e9) print(#s)")
  T.check_exit(code, 1, o, e)
  T.has(e, "not enough memory (lancer's memory cap is 1024 MB)")
  -- A script may catch it, as any error, and go on: its memory is back.
  o, e, code = run(dir, "--sandbox --max-memory 32", [[
local ok, err = pcall(string.rep, "x", 1e8)
print(ok, err)
local t = {} for i = 1, 1e5 do t[i] = i end
print(#t)
]])
  T.check_exit(code, 0, o, e)
  T.eq(o, "false\tnot enough memory\n100000\n", "stdout")
  cleanup(dir)
end)

T.test("memory cap: a huge image or mesh from the core fails, naming the cap", function()
  local dir = layout()
  local o, e, code = run(dir, "--sandbox --max-memory 64",
    "require('lancer').image{width = 8000, height = 8000}")
  T.check_exit(code, 1, o, e)
  T.has(e, "scene/scene.lua:1: out of memory for a 8000x8000 image (lancer's memory " ..
           "cap is ")
  local f = assert(io.open(dir .. "/scene/big.obj", "w"))
  for i = 1, 300000 do f:write("v ", i, " ", i % 7, " 0\n") end
  for i = 1, 299998 do f:write("f ", i, " ", i + 1, " ", i + 2, "\n") end
  f:close()
  o, e, code = run(dir, "--sandbox --max-memory 8",
                   "print(require('lancer').load_obj('scene/big.obj'))")
  T.check_exit(code, 1, o, e)
  T.has(e, "bad argument #1 to 'load_obj' (out of memory reading 'scene/big.obj' at " ..
           "line ")
  T.has(e, "(lancer's memory cap is ")
  o, e, code = run(dir, "--sandbox --max-memory 64")
  T.check_exit(code, 0, o, e)
  T.eq(o, "lancer.Mesh (300000 vertices, 299998 faces)\n", "under a larger cap")
  cleanup(dir)
end)

-- PNG's CRC-32 (ISO 3309), for a header written by hand.
local function crc32(s)
  local c = 0xffffffff
  for i = 1, #s do
    c = c ~ s:byte(i)
    for _ = 1, 8 do c = (c >> 1) ~ (0xedb88320 & -(c & 1)) end
  end
  return c ~ 0xffffffff
end

-- A 141-byte PNG whose header claims w x h: a 2x1 one's, its IHDR rewritten.
local function claiming_png(path, w, h)
  local small = path .. ".small.png"
  require("lancer").image{width = 2, height = 1}:save(small)
  local png = T.slurp(small)
  os.remove(small)
  local ihdr = "IHDR" .. string.pack(">I4I4", w, h) .. png:sub(25, 29)
  T.write(path, png:sub(1, 12) .. ihdr .. string.pack(">I4", crc32(ihdr)) .. png:sub(34))
end

-- The header's size meets the core's counted allocations (the image, then
-- the rows) before libpng reads a row: a 16000x16000 claim (3 GB of floats)
-- is refused with the cap's message, in a process whose address space is
-- held to 100 MB, so that the system could not have given it either.
T.test("memory cap: a PNG whose header claims a huge size is refused first", function()
  local dir = layout()
  claiming_png(dir .. "/scene/huge.png", 16000, 16000)
  local script = [[
local lancer = require "lancer"
print(pcall(lancer.load_png, "scene/huge.png"))
print(pcall(lancer.image_texture, {path = "scene/huge.png"}))
]]
  local o, e, code = run(dir, "--sandbox --max-memory 64", script)
  T.check_exit(code, 0, o, e)
  local cap = "out of memory for a 16000x16000 image (lancer's memory cap is 63."
  T.has(o, "false\tbad argument #1 to 'lancer.load_png' (" .. cap)
  T.has(o, "false\tbad argument #1 to 'lancer.image_texture' (field 'path': " .. cap)
  -- A sanitized build reserves terabytes of shadow memory: no ulimit there.
  local build = LANCER:gsub("/bin/lancer$", "")
  if os.execute(("nm %s 2>/dev/null | grep -q __asan_"):format(
      q(build .. "/liblancer.a"))) then
    cleanup(dir)
    return
  end
  T.write(dir .. "/scene/scene.lua", script)
  o, e, code = T.run(("cd %s && ulimit -v 102400 && %s --sandbox --max-memory 64 " ..
                      "scene/scene.lua"):format(q(dir), q(LANCER)))
  T.check_exit(code, 0, o, e)
  local _, n = o:gsub(cap:gsub("%p", "%%%0"), "")
  T.eq(n, 2, "both refused by the cap within 100 MB of address space:\n" .. o)
  cleanup(dir)
end)

T.test("time cap: a Lua loop stops, with pcall, coroutines or xpcall around it", function()
  local dir = layout()
  for _, script in ipairs{
    "local n = 0\nwhile true do n = n + 1 end",
    "while true do pcall(function() while true do end end) end",
    "local co = coroutine.wrap(function() while true do end end)\n" ..
    "while true do pcall(co) end",
    "local function spin() while true do end end\nwhile true do xpcall(spin, spin) end",
  } do
    local o, e, code, secs = run(dir, "--sandbox --max-seconds 0.5", script)
    T.check_exit(code, 4, o, e)
    T.has(e, "time cap reached (lancer's time cap is 0.5 s)")
    assert(secs < 2, ("%q stopped after %.2f s"):format(script, secs))
  end
  -- Without --sandbox too, at the line that loops.
  local o, e, code = run(dir, "--max-seconds 0.3",
                         "local x = 1\nwhile x do x = x + 1 end")
  T.check_exit(code, 4, o, e)
  T.has(e, "lancer: scene/scene.lua:2: time cap reached (lancer's time cap is 0.3 s)")
  cleanup(dir)
end)

-- Lua runs finalizers without hooks: a loop in __gc is not stopped by the
-- time cap but, as C code, by the watchdog 1 s past it (docs/manual.md,
-- "Untrusted scenes: the sandbox"), whether the collector runs it during
-- the script, at its end, or after the cap stopped the script. timeout
-- keeps a watchdog that failed from hanging the suite.
T.test("time cap: a loop in a __gc finalizer ends the process 1 s past the cap",
       function()
  local dir = layout()
  local gc = "setmetatable({}, {__gc = function() while true do end end})"
  local limit = have_timeout() and "timeout 10 " or ""
  for _, script in ipairs{gc .. " collectgarbage() print('not reached')", gc,
                          gc .. "\nwhile true do end"} do
    T.write(dir .. "/scene/scene.lua", script)
    local t0 = now()
    local o, e, code = T.run(("cd %s && %s%s --sandbox --max-seconds 0.5 " ..
                              "scene/scene.lua"):format(q(dir), limit, q(LANCER)))
    local secs = now() - t0
    T.check_exit(code, 4, o, e)
    T.has(e, "lancer: time cap reached (lancer's time cap is 0.5 s), in code that " ..
             "cannot be stopped: ending the process", script)
    T.eq(o, "", script .. ": stdout")
    assert(secs > 1.3 and secs < 3, ("%q ended after %.2f s"):format(script, secs))
  end
  cleanup(dir)
  -- The manual says so, in these words.
  local manual = T.slurp(ROOT .. "/docs/manual.md")
  local section = manual:match("\n## Untrusted scenes: the sandbox\n(.-)\n## ")
  assert(section, "no sandbox section in docs/manual.md")
  section = section:gsub("%s+", " ")
  T.has(section, "a loop in a finalizer (a `__gc` metamethod)", "the manual")
  T.has(section, "1 s past the cap lancer ends the process, with exit 4 and the line " ..
                 "`lancer: time cap reached (lancer's time cap is 0.5 s), in code that " ..
                 "cannot be stopped: ending the process`", "the manual")
end)

local LONG_RENDER = [[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 1, 0}}}
s:add(lancer.sphere{center = {0, 1, 0}, radius = 1},
      lancer.point_light{position = {2, 4, -3}, intensity = 25})
print(s:render{width = 2000, height = 2000, samples = 256})
]]

-- A render stops at the core's next look between tiles (every 0.1 s):
-- measured 0.04-0.14 s late at 256 samples per pixel on 2 cores.
T.test("time cap: a long render stops within 0.5 s of the cap", function()
  local dir = layout()
  local o, e, code, secs = run(dir, "--sandbox --max-seconds 1", LONG_RENDER)
  T.check_exit(code, 4, o, e)
  T.has(e, "lancer: scene/scene.lua:5: time cap reached in a render (lancer's time " ..
           "cap is 1 s)")
  assert(secs < 1.5, ("the render stopped after %.2f s"):format(secs))
  -- A frame of an animation likewise: the frames after it do not start.
  o, e, code, secs = run(dir, "--sandbox --max-seconds 1 --sandbox-out out", [[
local lancer = require "lancer"
lancer.animate{frames = 5, output = "out/f_%d.png",
  render = {width = 2000, height = 2000, samples = 256}, frame = function(f)
    local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 1, 0}}}
    s:add(lancer.sphere{center = {0, 1, 0}, radius = 1},
          lancer.point_light{position = {2, 4, -3}, intensity = 25})
    return s
  end}
]])
  T.check_exit(code, 4, o, e)
  T.has(e, "time cap reached (lancer's time cap is 1 s)")
  assert(not e:find("frame 2", 1, true), "a frame began after the time cap:\n" .. e)
  assert(secs < 1.5, ("the animation stopped after %.2f s"):format(secs))
  cleanup(dir)
end)

T.test("time cap: C code that does not stop ends the process 1 s after", function()
  local dir = layout()
  -- A pattern match that backtracks for hours, inside one C call.
  local o, e, code, secs = run(dir, "--sandbox --max-seconds 0.5",
    "print(('a'):rep(3000):find(('.-'):rep(20) .. 'b'))")
  T.check_exit(code, 4, o, e)
  T.has(e, "lancer: time cap reached (lancer's time cap is 0.5 s), in code that " ..
           "cannot be stopped: ending the process")
  assert(secs > 1.3 and secs < 3, ("ended after %.2f s"):format(secs))
  cleanup(dir)
end)

T.test("sandbox: usage errors exit 2 before the script runs", function()
  local MB = "option '--max-memory' needs a whole number of megabytes (0: no cap), got "
  local S = "option '--max-seconds' needs a number of seconds from 0 (no cap) " ..
            "to 1e9, got "
  local dir = layout()
  T.write(dir .. "/scene/scene.lua", "print('the script ran')")
  for _, c in ipairs{
    {"--sandbox --sandbox-out nowhere",
     "option '--sandbox-out' needs an existing folder, got 'nowhere'"},
    {"--sandbox --sandbox-out secret.txt",
     "option '--sandbox-out' needs an existing folder, got 'secret.txt'"},
    {"--sandbox-out out", "option '--sandbox-out' needs --sandbox"},
    {"--sandbox --allow-bytecode", "option '--allow-bytecode' cannot go with --sandbox"},
    {"--max-memory 12x", MB .. "'12x'"}, {"--max-memory -1", MB .. "'-1'"},
    {"--max-seconds -1", S .. "'-1'"}, {"--max-seconds nan", S .. "'nan'"},
    {"--max-seconds 0x10", S .. "'0x10'"},
    {"--max-seconds=", "option '--max-seconds' needs a value"},
    {"--max-memory=", "option '--max-memory' needs a value"},
    {"--sandbox -i", "option '--sandbox' runs a script, '-' or -e code, not the prompt"},
    {"--max-seconds 5 -i", "option '--max-seconds' cannot go with the prompt"},
    {"--sandbox --video x.mp4",
     "option '--video' cannot go with --sandbox (it runs ffmpeg)"},
    {"--sandbox --accuracy --knob samples=1,2",
     "option '--accuracy' cannot go with --sandbox"},
    {"--sandbx", "unknown option '--sandbox'; did you mean '--sandbox'?"},
  } do
    local o, e, code = run(dir, c[1])
    T.check_exit(code, 2, o, e)
    if c[1] ~= "--sandbx" then T.has(e, "lancer: " .. c[2], c[1]) end
    T.eq(o, "", c[1] .. ": stdout")
  end
  cleanup(dir)
end)

T.test("sandbox: a plain scene renders and saves as without it; -e code too", function()
  local dir = layout()
  local o, e, code, secs = run(dir, "--sandbox --sandbox-out out", [[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 1, 0}}}
s:add(lancer.sphere{center = {0, 1, 0}, radius = 1},
      lancer.point_light{position = {2, 4, -3}, intensity = 25})
local img, st = s:render{width = 32, height = 24}
img:save(arg[1])
print(st.rays.camera, os.time() > 0, math.random(1, 6), #arg)
]], "out/plain.png")
  T.check_exit(code, 0, o, e)
  local dice = output_of(q(LANCER) .. " -e 'print(math.random(1, 6))'"):gsub("\n", "")
  T.eq(o, "768\ttrue\t" .. dice .. "\t1\n", "stdout: the same seed as without")
  assert(exists(dir .. "/out/plain.png"), "no image written")
  assert(secs < 5, ("a tiny scene took %.1f s"):format(secs))
  o, e, code = T.run(q(LANCER) .. " --sandbox -e 'os.execute(\"true\")'")
  T.check_exit(code, 1, o, e)
  T.has(e, "(command line):1: sandbox: os.execute(\"true\") is refused")
  cleanup(dir)
end)

T.test("lancer.sandbox: run and command build the sandboxed command line", function()
  local sandbox = require "lancer.sandbox"
  local dir = layout()
  T.write(dir .. "/scene/scene.lua", "print('args', ...) os.execute('true')")
  T.eq(sandbox.command{script = "a b.lua", out = "o'ut", max_memory = 64,
                       max_seconds = 0.5, args = {"x"}, options = {"--stats"}},
       "'lancer' '--sandbox' '--sandbox-out' 'o'\\''ut' '--max-memory' '64' " ..
       "'--max-seconds' '0.5' '--stats' '--' 'a b.lua' 'x'", "command")
  local log = dir .. "/log.txt"
  local ok, why, code = sandbox.run{lancer = LANCER, script = dir .. "/scene/scene.lua",
                                    args = {"1", "2"}, log = log}
  T.eq(ok, nil, "run of a scene that tries os.execute")
  T.eq(code, 1, "its exit status")
  T.has(why, "exited 1")
  T.has(T.slurp(log), "args\t1\t2\n")
  T.has(T.slurp(log), "sandbox: os.execute(\"true\") is refused")
  T.write(dir .. "/scene/scene.lua", "while true do end")
  ok, why, code = sandbox.run{lancer = LANCER, script = dir .. "/scene/scene.lua",
                              max_seconds = 0.2, log = log}
  T.eq(code, 4, "the time cap's exit status")
  T.has(why, "(the time cap)")
  T.has(T.slurp(log), "time cap reached (lancer's time cap is 0.2 s)")
  T.write(dir .. "/scene/scene.lua", "print(1)")
  T.eq(sandbox.run{lancer = LANCER, script = dir .. "/scene/scene.lua", log = log,
                   options = {"--width", "8"}}, true, "run")
  T.eq(T.slurp(log), "1\n", "the log of a run")
  T.check_error(function() sandbox.run{script = "x", max_memory = 1.5} end,
                "test_sandbox.lua:", "bad argument #1 to 'run'", "megabytes are whole")
  T.check_error(function() sandbox.command{scrip = "x"} end,
                "bad argument #1 to 'command' (unknown field 'scrip')")
  T.check_error(function() sandbox.command{} end, "field 'script': required, got nil")
  cleanup(dir)
end)

-- An embedder's host: the script in argv[3] run in a sandboxed state that
-- reads below argv[1], writes below argv[2], with a 64 MB and 1 s cap.
local HOST_C = [[
#include <stdio.h>
#include <lauxlib.h>
#include "lancer_sandbox.h"

int main(int argc, char **argv)
{
    char err[256];
    lancer_sandbox_opts o = {argv[1], argv[2], 64000000, 1.0,
                             "lua/?.lua;lua/?/init.lua", NULL};
    lua_State *L = lancer_sandbox_open(&o, err, sizeof err);
    int status;
    if (argc != 4 || L == NULL) {
        fprintf(stderr, "%s\n", L ? "usage: host READ WRITE SCRIPT" : err);
        return 2;
    }
    status = luaL_loadfilex(L, argv[3], "t");
    if (status == LUA_OK)
        status = lua_pcall(L, 0, 0, 0);
    if (status != LUA_OK)
        fprintf(stderr, "%s\n", lua_tostring(L, -1));
    status = status != LUA_OK ? (lancer_sandbox_timed_out(L) ? 4 : 1) : 0;
    lancer_sandbox_close(L);
    return status;
}
]]

T.test("lancer_sandbox_open: an embedder's state refuses, caps, runs lancer", function()
  local build = LANCER:gsub("/bin/lancer$", "")
  local dir = layout()
  T.write(dir .. "/host.c", HOST_C)
  local objs = output_of("ls " .. q(build) .. "/obj/lua/*.o"):gsub("\n", " ")
  -- A sanitized build's objects need the sanitizers' runtimes (as test_docs.lua).
  local san = os.execute(("nm %s 2>/dev/null | grep -q __asan_"):format(
    q(build .. "/liblancer.a"))) and "-fsanitize=address,undefined " or ""
  local cc = ("cc -std=c99 %s-D_POSIX_C_SOURCE=200809L -I%s " ..
              "$(pkg-config --cflags lua5.4) " ..
              "-o %s %s %s %s/obj/cli/main_sandbox.o %s/obj/cli/main_caps.o %s/liblancer.a " ..
              "$(pkg-config --libs lua5.4) $(PKG_CONFIG_PATH=%s pkg-config --libs lancer) " ..
              "2>&1"):format(
              san, q(ROOT .. "/src"), q(dir .. "/host"), q(dir .. "/host.c"), objs,
              q(build), q(build), q(build), q(build))
  local o, e, code = T.run(cc)
  T.check_exit(code, 0, o, e)
  local function host(script)
    T.write(dir .. "/scene/scene.lua", script)
    return T.run(("cd %s && %s %s %s %s"):format(q(ROOT), q(dir .. "/host"),
                 q(dir .. "/scene"), q(dir .. "/out"), q(dir .. "/scene/scene.lua")))
  end
  o, e, code = host(PROBE .. [[
local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 1, 0}}}
s:add(lancer.sphere{center = {0, 1, 0}, radius = 1},
      lancer.point_light{position = {2, 4, -3}, intensity = 25})
probe("save", function() return s:render{width = 8, height = 6}:save("]] ..
    dir .. [[/out/host.png") end)
probe("saveout", function() return s:render{width = 8, height = 6}:save("host.png") end)
probe("execute", function() return os.execute("true") end)
probe("passwd", function() return io.open("/etc/passwd") end)
probe("debug", function() return debug.traceback() end)
probe("hook", function() return lancer.set_host_hook end)
probe("host", function() return require "lancer.host" end)
]])
  T.check_exit(code, 0, o, e)
  local got = check_refused(o, {
    saveout = "sandbox: not writing 'host.png': it does not resolve below the " ..
              "output folder",
    execute = "os.execute(\"true\") is refused", passwd = "not reading '/etc/passwd'",
    debug = "debug.traceback is refused", host = "require 'lancer.host' is refused"})
  T.eq(got.save.verdict, "ALLOWED", "a save below write_dir")
  T.eq(got.hook.verdict, "REFUSED", "set_host_hook is gone")
  assert(exists(dir .. "/out/host.png") and not exists(ROOT .. "/host.png"),
         "saved where?")
  o, e, code = host("local t = {} for i = 1, 1e8 do t[i] = i end")
  T.check_exit(code, 1, o, e)
  T.has(e, "not enough memory")
  o, e, code = host("while true do end")
  T.check_exit(code, 4, o, e)
  T.has(e, "scene.lua:1: time cap reached (lancer's time cap is 1 s)")
  cleanup(dir)
end)
