-- test_pipeline.lua: issue 16's parts 1, 3 and 5 from Lua and the command
-- line: regions equal to the whole frame (every sampler, adaptive sampling
-- included), alpha as coverage, tiles merged to the bytes of the whole frame
-- (also on GNU parallel), -D, --seed, --threads, 1-48x4, and make install.
local T = require "harness"
local lancer = require "lancer"

local q = T.quote
-- Absolute: the command runs in other folders.
local function absolute(path)
  if path:sub(1, 1) == "/" then return path end
  local p = assert(io.popen("pwd"))
  local cwd = p:read("l")
  p:close()
  return cwd .. "/" .. path
end
local LANCER = absolute(T.lancer)
local L = q(LANCER)
local HERE = "test_pipeline.lua:"

-- Soft shadows from an area light, a glossy floor, a mirror: many pixels near
-- any noise target, so adaptive sampling's passes differ from pixel to pixel.
local function noisy_scene()
  local s = lancer.scene{camera = lancer.camera{from = {0, 1.5, -5}, at = {0, 1, 0}}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                     material = lancer.material{color = 0.8, kr = 0.3, glossiness = 8}})
  s:add(lancer.sphere{center = {-0.6, 1, 0}, radius = 1,
                      material = lancer.material{color = {0.9, 0.2, 0.15}, ks = 0.5}})
  s:add(lancer.sphere{center = {1.2, 0.5, -1}, radius = 0.5,
                      material = lancer.material{kr = 0.9, kd = 0.1}})
  s:add(lancer.quad{corner = {-1, 3, -2}, u = {2, 0, 0}, v = {0, 0, 1.5},
                    material = lancer.material{emission = {6, 6, 6}}})
  return s
end

-- Pixels of part that differ from the same pixels of whole.
local function differing(part, whole)
  local r, bad = part.region, 0
  for y = 1, part.height do
    for x = 1, part.width do
      local a, b, c = part:pixel(x, y)
      local d, e, f = whole:pixel(x + r[1], y + r[2])
      if a ~= d or b ~= e or c ~= f then bad = bad + 1 end
    end
  end
  return bad
end

T.test("render{region}: every pixel equals the whole frame's, every sampler", function()
  local s = noisy_scene()
  local cases = {
    {samples = 1}, {samples = 4}, {samples = 9, sampler = "jitter"},
    {samples = 8, sampler = "random"},
    {samples = 32, noise = 0.03, min_samples = 2},                   -- 4 passes after the first
    {samples = 16, noise = 0.05, min_samples = 2, sampler = "random"},
  }
  local regions = {{0, 0, 53, 12}, {7, 9, 40, 31}, {52, 36, 53, 37}, {0, 20, 53, 37}}
  for _, o in ipairs(cases) do
    o.width, o.height, o.light_samples, o.cone_samples = 53, 37, 4, 4
    local whole = s:render(o)
    for _, r in ipairs(regions) do
      o.region = r
      local part = s:render(o)
      T.eq(part.width .. "x" .. part.height, (r[3] - r[1]) .. "x" .. (r[4] - r[2]), "size")
      T.eq(table.concat(part.region, ","), table.concat(r, ","), "img.region")
      T.eq(table.concat(part.frame, ","), "53,37", "img.frame")
      T.eq(differing(part, whole), 0, ("pixels differing, %s %s region %s"):format(
        o.sampler or "sobol", o.noise and "adaptive" or "", table.concat(r, ",")))
    end
    o.region = nil
  end
end)

T.test("render{region}: bad regions name the field", function()
  local s = noisy_scene()
  T.check_error(function() s:render{width = 8, height = 8, region = {0, 0, 9, 8}} end,
                HERE, "'render'", "field 'region'", "0 <= x0 < x1 <= 8", "got {0, 0, 9, 8}")
  T.check_error(function() s:render{width = 8, height = 8, region = {2, 0, 2, 8}} end,
                HERE, "field 'region'", "got {2, 0, 2, 8}")
  T.check_error(function() s:render{width = 8, height = 8, region = {0, 0, 8}} end,
                HERE, "field 'region'", "{x0, y0, x1, y1} expected, got 3 values")
  T.check_error(function() s:render{width = 8, height = 8, region = {0, 0.5, 8, 8}} end,
                HERE, "field 'region'", "item 2: a whole number")
end)

-- A quad covering x <= 0, which looking down +z with y up is the right half
-- of the view: columns right of the centre are covered, left of it not, and
-- the centre column (its middle on the edge) exactly half: 16 Sobol' or 4x4
-- jittered points put 8 on each side.
T.test("render{alpha}: coverage per pixel, 0, 1/2 and 1 exactly", function()
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, -1}, at = {0, 0, 0}, fov = 90},
                         background = {1, 1, 1}}
  s:add(lancer.quad{corner = {-10, -10, 0}, u = {10, 0, 0}, v = {0, 20, 0},
                    material = lancer.material{emission = {0.25, 0.5, 1}, kd = 0}})
  for _, sampler in ipairs{"sobol", "jitter"} do
    local img, st = s:render{width = 7, height = 3, samples = 16, sampler = sampler,
                             alpha = true}
    assert(img.alpha, "the image has alpha")
    for x = 1, 7 do
      local r, g, b, a = img:pixel(x, 2)
      local want = x > 4 and 1 or x == 4 and 0.5 or 0
      T.eq(a, want, ("alpha at column %d, %s"):format(x, sampler))
      -- Misses add nothing: the white background is transparent.
      T.eq(b, want, ("blue at column %d (emission 1 times coverage)"):format(x))
      T.eq(r, want * 0.25, "red")
    end
    T.eq(st.rays.camera, 7 * 3 * 16, "camera rays")
  end
  local plain = s:render{width = 7, height = 3, samples = 16}
  T.eq(plain.alpha, false, "no alpha unless asked")
  T.eq(select("#", plain:pixel(7, 2)), 3, "pixel's values without alpha")
  T.eq(select(3, plain:pixel(1, 2)), 1.0, "the background, without alpha")
end)

T.test("an sRGB PNG reads back through the exact sRGB curve, darks included", function()
  -- libpng's simplified reader went through 8 bits and a 2.2 power: 0.001
  -- read 0, 0.03 read 0.0235 (8 bits) and 0.0258 (16 bits).
  local dir = T.temp_dir()
  local function srgb(v) return v <= 0.0031308 and 12.92 * v or 1.055 * v ^ (1 / 2.4) - 0.055 end
  local function linear(c) return c <= 0.04045 and c / 12.92 or ((c + 0.055) / 1.055) ^ 2.4 end
  for _, v in ipairs{0.0004, 0.001, 0.01, 0.03, 0.1, 0.5, 0.9} do
    local img = lancer.image{width = 1, height = 1, color = {v, v, v}}
    img:save(dir .. "/8.png")
    img:save(dir .. "/16.png", {depth = 16})
    local want8 = linear(math.floor(srgb(v) * 255 + 0.5) / 255)
    local want16 = linear(math.floor(srgb(v) * 65535 + 0.5) / 65535)
    T.near(lancer.load_png(dir .. "/8.png"):pixel(1, 1), want8, 1e-7, "8 bits, " .. v)
    T.near(lancer.load_png(dir .. "/16.png"):pixel(1, 1), want16, 1e-7, "16 bits, " .. v)
    T.near(want16, v, math.max(2e-5 * v, 1.2e-6), "16 bits keep " .. v)
  end
end)

T.test("save and load_exr from Lua: float exact, options checked", function()
  local dir = T.temp_dir()
  local img = lancer.image{width = 3, height = 2, color = {0.1, 2.5, 1e-3}}
  img:set(2, 2, 7, -1, 65504, 0.25)                  -- gives it alpha
  img:save(dir .. "/f.exr", {pixel = "float", compression = "piz", tile = 2, alpha = true})
  local back = lancer.load_exr(dir .. "/f.exr")
  T.eq(back.width .. "x" .. back.height, "3x2", "size")
  local r, g, b, a = back:pixel(2, 2)
  T.eq(r, 7.0, "r"); T.eq(g, -1.0, "g"); T.eq(b, 65504.0, "b"); T.eq(a, 0.25, "a")
  T.eq(select(2, back:pixel(1, 1)), 2.5, "g at 1, 1")
  img:save(dir .. "/h.exr")                           -- half, zip, no alpha
  local h = lancer.load_exr(dir .. "/h.exr")
  T.eq(h.alpha, false, "saved without alpha")
  T.eq(select(1, h:pixel(1, 1)), 0.0999755859375, "0.1 as a half")
  img:save(dir .. "/d.png", {depth = 16, encoding = "linear"})
  T.eq(select(2, lancer.load_png(dir .. "/d.png", {encoding = "linear"}):pixel(1, 1)),
       1.0, "16-bit PNG, clamped")
  T.check_error(function() img:save(dir .. "/x.png", {depth = 12}) end, HERE,
                "'save'", "field 'depth'", "must be 8 or 16, got 12")
  T.check_error(function() img:save(dir .. "/x.exr", {pixel = "double"}) end, HERE,
                "field 'pixel'", "expected one of 'half', 'float'")
  T.check_error(function() lancer.image{width = 1, height = 1}:save(dir .. "/x.png",
                {alpha = true}) end, HERE, "field 'alpha'", "the image has none")
  T.check_error(function() lancer.load_exr(dir .. "/d.png") end, HERE, "'load_exr'",
                "cannot read '" .. dir .. "/d.png'")
  T.check_error(function() lancer.merge_tiles(dir .. "/m.exr", {dir .. "/f.exr", 3}) end,
                HERE, "'merge_tiles'", "item 2: file name expected, got number")
  os.execute("rm -rf " .. q(dir))
end)

local STILL = [[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 1.5, -5}, at = {0, 1, 0}}}
s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                   material = lancer.material{color = 0.8, kr = 0.3, glossiness = 8}})
s:add(lancer.sphere{center = {0, 1, 0}, radius = 1,
                    material = lancer.material{color = {0.9, 0.2, 0.15}, ks = 0.5}})
s:add(lancer.quad{corner = {-1, 3, -2}, u = {2, 0, 0}, v = {0, 0, 1.5},
                  material = lancer.material{emission = {6, 6, 6}}})
s:render{width = 61, height = 45, samples = 32, noise = 0.03, min_samples = 2,
         light_samples = 4, cone_samples = 4, alpha = true}:save(arg[1], {alpha = true})
]]

T.test("--tile K/N on GNU parallel, then --merge: the whole frame's bytes", function()
  if os.execute("command -v parallel >/dev/null 2>&1") ~= true then
    error("GNU parallel is not installed: run tools/install-deps.sh test")
  end
  local dir = T.temp_dir()
  T.write(dir .. "/still.lua", STILL)
  local env = "HOME=" .. q(dir) .. " "
  for _, ext in ipairs{"png", "exr"} do
    local whole = dir .. "/whole." .. ext
    local _, err, code = T.run(("%s %s %s"):format(L, q(dir .. "/still.lua"), q(whole)))
    T.eq(code, 0, "whole frame: " .. err)
    _, err, code = T.run(("cd %s && %s parallel --will-cite -j2 %s --tile {}/4 still.lua " ..
                          "part.%s ::: 0 1 2 3"):format(q(dir), env, L, ext))
    T.eq(code, 0, "parallel: " .. err)
    _, err, code = T.run(("cd %s && %s --merge merged.%s part.tile-*-of-4.%s"):format(
      q(dir), L, ext, ext))
    T.eq(code, 0, "merge: " .. err)
    local a, b = T.slurp(whole), T.slurp(dir .. "/merged." .. ext)
    assert(a and #a > 1000, "no whole frame")
    assert(a == b, ext .. ": the merged frame differs from the whole frame")
    assert(T.slurp(dir .. "/part.tile-0-of-4." .. ext) ~= a, "a part is the whole?")
  end
  -- A missing part is named by the pixels it leaves.
  local _, err, code = T.run(("cd %s && %s --merge m.png part.tile-0-of-4.png " ..
                              "part.tile-2-of-4.png part.tile-3-of-4.png"):format(q(dir), L))
  T.eq(code, 1, "merge with a part missing")
  T.eq(err, "lancer: cannot merge into 'm.png': the parts leave 671 of the 61x45 frame's " ..
       "pixels uncovered, the first at (0, 11) counted from 0 at the top-left\n", "stderr")
  os.execute("rm -rf " .. q(dir))
end)

T.test("--region: a rectangle saved with its place, merged with the rest", function()
  local dir = T.temp_dir()
  T.write(dir .. "/still.lua", STILL)
  local function run(args)
    local _, err, code = T.run(("cd %s && %s %s still.lua out.exr"):format(q(dir), L, args))
    T.eq(code, 0, args .. ": " .. err)
  end
  run("")
  run("--region 0,0,61,20")
  run("--region 0,20,30,45")
  run("--region 30,20,61,45")
  local img = lancer.load_exr(dir .. "/out.region-0-20-30-45.exr")
  T.eq(table.concat(img.region, ","), "0,20,30,45", "the part's place")
  T.eq(table.concat(img.frame, ","), "61,45", "the frame")
  local _, err, code = T.run(("cd %s && %s --merge m.exr out.region-*.exr && cmp m.exr out.exr")
    :format(q(dir), L))
  T.eq(code, 0, "merged regions: " .. err)
  local out
  out, err, code = T.run(("cd %s && %s --region 0,0,62,10 still.lua x.png"):format(q(dir), L))
  T.eq(code, 2, "a region outside the frame")
  T.eq(err, "lancer: option '--region 0,0,62,10' is outside the 61x45 frame; try " ..
       "'lancer --help'\n", "stderr")
  out, err, code = T.run(("%s --region 5,0,5,1 still.lua"):format(L))
  T.eq(code, 2, "an empty region")
  assert(err:find("option '--region' needs X0 < X1 and Y0 < Y1, got '5,0,5,1'", 1, true), err)
  out, err, code = T.run(("%s --tile 4/4 still.lua"):format(L))
  T.eq(code, 2, "tile 4 of 4")
  assert(err:find("option '--tile' needs K/N with 0 <= K < N", 1, true), err)
  out, err, code = T.run(("%s --tile 0/2 --region 0,0,1,1 still.lua"):format(L))
  T.eq(code, 2, "--tile with --region")
  os.execute("rm -rf " .. q(dir))
end)

T.test("-D NAME=VALUE, --seed, --threads: what the script and its renders see", function()
  local dir = T.temp_dir()
  T.write(dir .. "/d.lua", [[
print(size, math.type(size), name, type(name), ratio, hex, quoted)
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 0, -3}, at = {0, 0, 0}}}
s:add(lancer.sphere{center = {0, 0, 0}, radius = 1},
      lancer.point_light{position = {2, 2, -3}, intensity = 10})
local img, st = s:render{width = 40, height = 40, samples = 4, seed = 1, threads = 2}
print(st.threads, math.random(1000000))
img:save(arg[1])
]])
  local out, err, code = T.run(("cd %s && %s -D size=2 -D name=ball -D ratio=0.5 -Dhex=0x10 " ..
                                "-D 'quoted=a b=c' d.lua a.png"):format(q(dir), L))
  T.eq(code, 0, err)
  T.eq(out:match("^[^\n]*"), "2\tinteger\tball\tstring\t0.5\t16\ta b=c", "the globals")
  T.eq(out:match("\n(%d+)"), "2", "threads as the script asks")
  local seeded
  seeded, err, code = T.run(("cd %s && %s --seed 7 --threads 1 d.lua b.png"):format(q(dir), L))
  T.eq(code, 0, err)
  T.eq(seeded:match("\n(%d+)"), "1", "--threads wins over the script")
  assert(seeded:match("\t(%d+)\n$") ~= out:match("\t(%d+)\n$"), "math.random not reseeded")
  assert(T.slurp(dir .. "/a.png") ~= T.slurp(dir .. "/b.png"), "--seed changed no pixel")
  local again = T.run(("cd %s && %s --seed 7 d.lua c.png"):format(q(dir), L))
  T.eq(again:match("\t(%d+)\n$"), seeded:match("\t(%d+)\n$"), "math.random under --seed 7")
  T.eq(T.slurp(dir .. "/c.png"), T.slurp(dir .. "/b.png"), "the same seed, the same image")
  for _, bad in ipairs{{"-D print=1", "'print' is already a global"},
                       {"-D 9lives=1", "'9lives' is not a Lua name"},
                       {"-D end=1", "'end' is a Lua keyword"},
                       {"-D novalue", "option '-D' needs NAME=VALUE, such as size=2"},
                       {"--seed -1", "option '--seed' needs a whole number from 0"},
                       {"--threads 300", "option '--threads' needs a whole number of threads"}} do
    out, err, code = T.run(("cd %s && %s %s d.lua x.png"):format(q(dir), L, bad[1]))
    T.eq(code, 2, bad[1])
    assert(err:find(bad[2], 1, true), err)
  end
  os.execute("rm -rf " .. q(dir))
end)

T.test("--frames 1-9x4 is 1-9:4", function()
  local dir = T.temp_dir()
  T.write(dir .. "/a.lua", [[
require("lancer").animate{frames = 12, output = "f_%02d.png", frame = function() end}]])
  local a, err, code = T.run(("cd %s && %s --list-frames --frames 1-9x4,12 a.lua"):format(q(dir), L))
  T.eq(code, 0, err)
  T.eq(a, "f_01.png\nf_05.png\nf_09.png\nf_12.png\n", "frames listed")
  local b = T.run(("cd %s && %s --list-frames --frames 1-9:4,12 a.lua"):format(q(dir), L))
  T.eq(b, a, "the same as with ':'")
  local tiles = T.run(("cd %s && %s --list-frames --tile 1/3 --frame 5 a.lua"):format(q(dir), L))
  T.eq(tiles, "f_05.tile-1-of-3.png\n", "a part's file")
  local _, e2, c2 = T.run(("cd %s && %s --frames 1-9x0 a.lua"):format(q(dir), L))
  T.eq(c2, 2, "step 0")
  assert(e2:find("a step is a whole number from 1", 1, true), e2)
  os.execute("rm -rf " .. q(dir))
end)

-- make install into a temporary DESTDIR, then the stock lua5.4 with the paths
-- it searches under /usr/local moved into DESTDIR, and a C program built with
-- the installed lancer.pc.
T.test("make install: lancer, require 'lancer' from stock lua5.4, lancer.pc; uninstall",
       function()
  local build = LANCER:gsub("/bin/lancer$", "")
  local dest = T.temp_dir()
  local make = ("make -s --no-print-directory BUILD=%s DESTDIR=%s PREFIX=/usr/local"):format(
    q(build), q(dest))
  local _, err, code = T.run(make .. " install")
  T.eq(code, 0, "make install: " .. err)
  local root = dest .. "/usr/local"
  local out
  out, err, code = T.run(q(root .. "/bin/lancer") .. " -e 'print(lancer.version)'")
  T.eq(out, lancer.version .. "\n", "installed lancer: " .. err)
  -- Stock lua5.4's own search paths, /usr/local moved into DESTDIR; the others
  -- (/usr, ./) dropped so nothing else can answer.
  local function moved(path)
    local keep = {}
    for item in path:gmatch("[^;]+") do
      if item:find("^/usr/local/") then keep[#keep + 1] = dest .. item end
    end
    return table.concat(keep, ";")
  end
  local paths = T.run("env -u LUA_PATH -u LUA_CPATH -u LUA_PATH_5_4 -u LUA_CPATH_5_4 " ..
                      "lua5.4 -e 'print(package.path); print(package.cpath)'")
  local lpath, cpath = paths:match("^([^\n]*)\n([^\n]*)")
  local probe = T.temp_dir()
  T.write(probe .. "/p.lua", [[
local lancer = require "lancer"
local s = lancer.scene{camera = lancer.camera{from = {0, 0, -3}, at = {0, 0, 0}}}
s:add(lancer.sphere{center = {0, 0, 0}, radius = 1})
s:add(lancer.point_light{position = {0, 0, -3}, intensity = 9})   -- 9 / 2^2 at the front
local img = s:render{width = 3, height = 3}
print(lancer.version, package.searchpath("lancer", package.path),
      package.searchpath("lancer.core", package.cpath), img:pixel(2, 2))
]])
  out, err, code = T.run(("cd %s && env -u LUA_PATH -u LUA_CPATH LUA_PATH_5_4=%s " ..
                          "LUA_CPATH_5_4=%s lua5.4 p.lua"):format(q(probe), q(moved(lpath)),
                          q(moved(cpath))))
  T.eq(code, 0, "stock lua5.4: " .. err)
  T.eq(out, ("%s\t%s/share/lua/5.4/lancer/init.lua\t%s/lib/lua/5.4/lancer/core.so\t" ..
             "2.25\t2.25\t2.25\n"):format(lancer.version, root, root), "require 'lancer'")
  T.write(probe .. "/prog.c", [[
#include <stdio.h>
#include "lancer.h"
int main(void)
{
    lc_error err;
    lc_image *img = lc_image_new(2, 1, &err);
    lc_save_options o = lc_save_options_default();
    o.exr_pixel = LC_EXR_FLOAT;
    if (!img || lc_image_save_with(img, "x.exr", &o, &err))
        return 1;
    lc_image *back = lc_image_load_exr("x.exr", &err);
    printf("%s %dx%d\n", LC_VERSION, lc_image_width(back), lc_image_height(back));
    lc_image_free(back);
    lc_image_free(img);
    return 0;
}
]])
  out, err, code = T.run(("cd %s && cc -std=c99 -o prog prog.c $(PKG_CONFIG_PATH=%s " ..
                          "pkg-config --define-variable=prefix=%s --cflags --libs lancer) " ..
                          "&& ./prog"):format(q(probe), q(root .. "/lib/pkgconfig"), q(root)))
  T.eq(code, 0, "a C program against the installed core: " .. err)
  T.eq(out, lancer.version .. " 2x1\n", "its output")
  _, err, code = T.run(make .. " uninstall")
  T.eq(code, 0, "make uninstall: " .. err)
  T.eq(T.run("find " .. q(dest) .. " -type f"), "", "files left after uninstall")
  os.execute("rm -rf " .. q(dest) .. " " .. q(probe))
end)
