-- test_hdr.lua: lancer's Radiance .hdr reader: flat and run-length coded
-- files read right, and every malformed count (runs of 0, runs past a
-- scanline, data ending early, sizes past the caps, a bad header) fails at
-- once, naming the file and what is wrong, in a plain run and in --sandbox.
local T = require "harness"
local lancer = require "lancer"

local q = T.quote
local char = string.char

local HEADER = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n"

-- A file of the given bytes; its path.
local function file(bytes)
  local path = os.tmpname() .. ".hdr"
  local f = assert(io.open(path, "wb"))
  f:write(bytes)
  f:close()
  return path
end

-- The marker of a coded scanline of w pixels.
local function marker(w) return char(2, 2, w >> 8, w & 255) end

-- A literal span of the given bytes.
local function literal(...) return char(select("#", ...), ...) end

-- load_hdr and image_texture must both refuse the file, naming it and
-- every part given.
local function refused(bytes, ...)
  local path = file(bytes)
  local name = path:match("[^/]*$")
  T.check_error(function() lancer.load_hdr(path) end, name, ...)
  T.check_error(function() lancer.image_texture{path = path} end, name, ...)
  os.remove(path)
end

T.test("a coded file reads as written: runs, literals, a flat scanline after", function()
  -- 8x2: scanline 1 coded (R a run of 8 of 128, G literals, B a run, E a
  -- run of 129: (1, g/128, 0.25)); scanline 2 flat, as Radiance allows.
  local line1 = marker(8) .. char(128 + 8, 128)
             .. literal(0, 16, 32, 48, 64, 80, 96, 112)
             .. char(128 + 8, 32) .. char(128 + 8, 129)
  local line2 = string.rep(char(128, 64, 32, 130), 8)
  local path = file(HEADER .. "-Y 2 +X 8\n" .. line1 .. line2)
  local img = lancer.load_hdr(path)
  os.remove(path)
  T.eq(img.width, 8); T.eq(img.height, 2)
  for x = 1, 8 do
    local r, g, b = img:pixel(x, 1)
    T.eq(r, 1); T.eq(g, (x - 1) * 16 / 128); T.eq(b, 0.25)
    r, g, b = img:pixel(x, 2)
    T.eq(r, 2); T.eq(g, 1); T.eq(b, 0.5)
  end
end)

T.test("a flat file reads as written; an exponent of 0 is black", function()
  local path = file("#?RGBE\n# a comment\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=2\n\n" ..
                    "-Y 1 +X 3\n" ..
                    char(128, 64, 32, 130, 255, 255, 255, 0, 1, 2, 3, 136))
  local img = lancer.load_hdr(path)
  os.remove(path)
  local r, g, b = img:pixel(1, 1)
  T.eq(r, 2); T.eq(g, 1); T.eq(b, 0.5)
  r, g, b = img:pixel(2, 1)
  T.eq(r, 0); T.eq(g, 0); T.eq(b, 0)
  r, g, b = img:pixel(3, 1)
  T.eq(r, 1); T.eq(g, 2); T.eq(b, 3)          -- stored as is: EXPOSURE is not applied
end)

T.test("a truncated coded file fails at once, naming the scanline", function()
  -- The file of the report: a coded scanline stopping early (a reader that
  -- took the end of the file for counts of 0 never returned).
  refused(HEADER .. "-Y 1 +X 8\n" .. marker(8) .. char(128 + 8, 1),
          "needs at least 12 bytes of pixels, the file has 6")
  -- Long enough for its size, but scanline 2 stops after its red channel.
  local line = marker(8) .. literal(1, 2, 3, 4, 5, 6, 7, 8)
                .. char(128 + 8, 1, 128 + 8, 1, 128 + 8, 130)
  refused(HEADER .. "-Y 2 +X 8\n" .. line .. marker(8) .. char(128 + 8, 1),
          "the data ends in scanline 2 of 2")
  refused(HEADER .. "-Y 2 +X 8\n" .. line .. marker(8) .. literal(1, 2, 3, 4, 5, 6, 7, 8)
          .. char(4, 1), "the data ends in scanline 2 of 2")
  -- A flat file short of its last pixel.
  refused(HEADER .. "-Y 2 +X 4\n" .. string.rep(char(1, 1, 1, 128), 7),
          "needs at least 32 bytes of pixels, the file has 28")
end)

T.test("runs of length 0 and runs past the scanline's end are refused", function()
  local pad = string.rep(char(0), 64)   -- past the size check: the counts decide
  refused(HEADER .. "-Y 1 +X 8\n" .. marker(8) .. pad,
          "scanline 1: run of length 0 (channel 1, at pixel 1 of 8)")
  refused(HEADER .. "-Y 1 +X 8\n" .. marker(8) .. char(128 + 8, 1, 0) .. pad,
          "scanline 1: run of length 0 (channel 2, at pixel 1 of 8)")
  refused(HEADER .. "-Y 1 +X 8\n" .. marker(8) .. char(128 + 3, 1, 2, 5, 6, 0) .. pad,
          "scanline 1: run of length 0 (channel 1, at pixel 6 of 8)")
  -- 128 is a literal count (Radiance's rule), not a run of 0.
  refused(HEADER .. "-Y 1 +X 8\n" .. marker(8) .. char(128) .. pad,
          "scanline 1: literal of length 128 past the scanline's end")
  refused(HEADER .. "-Y 1 +X 8\n" .. marker(8) .. char(128 + 5, 1, 128 + 4, 1) .. pad,
          "scanline 1: run of length 4 past the scanline's end (channel 1, at pixel 6 "
          .. "of 8)")
  refused(HEADER .. "-Y 1 +X 8\n" .. marker(8) .. char(9) .. pad,
          "scanline 1: literal of length 9 past the scanline's end")
  refused(HEADER .. "-Y 1 +X 8\n" .. marker(9) .. pad,
          "scanline 1 says 9 pixels, the image is 8 wide")
end)

T.test("sizes of 0, past a side or past the pixel cap are refused before reading",
       function()
  refused(HEADER .. "-Y 1 +X 0\n", "the resolution line '-Y 1 +X 0' is not")
  refused(HEADER .. "-Y 0 +X 4\n", "is not '-Y height +X width'")
  refused(HEADER .. "-Y 2000000 +X 8\n", "is more than lancer's 1048576 pixels a side")
  refused(HEADER .. "-Y 99999999999999999999999 +X 8\n", "pixels a side")
  refused(HEADER .. "-Y 1048576 +X 1048576\n", "is more than lancer's 268435456 pixels")
  -- Within the caps, but far more than the file holds: refused before the
  -- 3 GB of pixels are asked for.
  refused(HEADER .. "-Y 16384 +X 16384\n" .. marker(16384),
          "a 16384x16384 image needs at least")
end)

T.test("a header without FORMAT, or with another, or without an end is refused",
       function()
  refused("#?RADIANCE\n\n-Y 1 +X 1\n" .. char(1, 1, 1, 128),
          "the header has no FORMAT=32-bit_rle_rgbe line")
  refused("#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n" .. char(1, 1, 1, 128),
          "its FORMAT is '32-bit_rle_xyze'")
  refused("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n-Y 1 +X 1\n", "the header has no end")
  refused(HEADER, "no resolution line")
  refused(HEADER .. "+Y 1 +X 1\n" .. char(1, 1, 1, 128), "is not '-Y height +X width'")
  refused(HEADER .. "-Y 1 +X 1 x\n" .. char(1, 1, 1, 128), "is not '-Y height +X width'")
  refused("#?RADIANCEX\n", "is not a Radiance .hdr image")
  refused("", "is not a Radiance .hdr image")
end)

T.test("the truncated file fails at once through the command, in and out of --sandbox",
       function()
  local dir = T.temp_dir()
  local f = assert(io.open(dir .. "/s.hdr", "wb"))
  f:write(HEADER .. "-Y 2 +X 8\n" .. marker(8) .. literal(1, 2, 3, 4, 5, 6, 7, 8)
          .. char(128 + 8, 1, 128 + 8, 1, 128 + 8, 130) .. marker(8) .. char(128 + 8))
  f:close()
  T.write(dir .. "/scene.lua",
          "local lancer = require 'lancer'\nlancer.image_texture{path = 's.hdr'}\n")
  local bin = T.lancer
  if bin:sub(1, 1) ~= "/" then bin = os.getenv("PWD") .. "/" .. bin end
  for _, options in ipairs{"", "--sandbox --max-seconds 20"} do
    local t0 = os.time()
    local o, e, code = T.run(("cd %s && %s %s scene.lua"):format(q(dir), q(bin),
                                                                  options))
    assert(code ~= 0, "the command succeeded: " .. o .. e)
    T.has(e, "s.hdr': the data ends in scanline 2 of 2", options)
    assert(os.time() - t0 <= 5, "it took " .. (os.time() - t0) .. " s")
  end
  os.execute("rm -rf " .. q(dir))
end)

T.test("a valid file too large for the memory cap is refused by it, naming the file",
       function()
  -- 4096x4096 coded (1.1 MB: runs of 127), 201 MB of pixels: past --max-memory 64.
  local runs = string.rep(char(255, 128), 32) .. char(128 + 32, 128)   -- 128 * 2^-7
  local line = marker(4096) .. runs .. runs .. runs .. string.rep(char(255, 129), 32)
               .. char(128 + 32, 129)
  local dir = T.temp_dir()
  local f = assert(io.open(dir .. "/big.hdr", "wb"))
  f:write(HEADER .. "-Y 4096 +X 4096\n" .. string.rep(line, 4096))
  f:close()
  T.write(dir .. "/scene.lua", "local lancer = require 'lancer'\n" ..
          "local img = lancer.load_hdr('big.hdr')\nprint(img:pixel(1, 1))\n")
  local bin = T.lancer
  if bin:sub(1, 1) ~= "/" then bin = os.getenv("PWD") .. "/" .. bin end
  local o, e, code = T.run(("cd %s && %s --max-memory 64 scene.lua"):format(q(dir),
                                                                           q(bin)))
  T.check_exit(code, 1, o, e)
  T.has(e, "cannot read 'big.hdr': out of memory for a 4096x4096 image")
  T.has(e, "lancer's memory cap is")
  o, e, code = T.run(("cd %s && %s scene.lua"):format(q(dir), q(bin)))
  T.check_exit(code, 0, o, e)
  T.has(o, "1.0\t1.0\t1.0")
  os.execute("rm -rf " .. q(dir))
end)
