-- test_simd.lua: the box test's three forms (LANCER_SIMD=0: scalar, 1: AVX at
-- most, unset: the best the processor has, AVX-512 where it can) give the
-- same image bytes, through the lancer command, on scenes whose hierarchies
-- are deep (meshes, many spheres, moved meshes, CSG, bounced light).
local T = require "harness"

local CASES = {
  {"scenes/bench/b3.lua", "60"},
  {"scenes/bench/b2.lua", "3000"},
  {"scenes/bench/instances.lua", "6"},
  {"scenes/csg.lua"},
  {"scenes/cornell.lua"},
}

for _, case in ipairs(CASES) do
  T.test(("%s: the same bytes with SIMD off, AVX, and the best"):format(case[1]), function()
    local dir = T.temp_dir()
    local bytes = {}
    for _, simd in ipairs{"0", "1", ""} do
      local out = ("%s/simd%s.png"):format(dir, simd)
      local cmd = ("%s%s --width 64 --height 48 --samples 2 %s"):format(
        simd ~= "" and "env LANCER_SIMD=" .. simd .. " " or "env -u LANCER_SIMD ",
        T.quote(T.lancer), T.quote(case[1]))
      -- The bench scripts take their size first, then the output.
      if case[2] then cmd = cmd .. " " .. case[2] end
      local o, e, code = T.run(cmd .. " " .. T.quote(out))
      T.check_exit(code, 0, o, e)
      bytes[#bytes + 1] = assert(T.slurp(out), "no image written: " .. out)
    end
    os.execute("rm -rf " .. T.quote(dir))
    T.eq(#bytes[1] > 100, true, "an image was written")
    T.eq(bytes[2] == bytes[1], true, "AVX against scalar")
    T.eq(bytes[3] == bytes[1], true, "the best against scalar")
  end)
end
