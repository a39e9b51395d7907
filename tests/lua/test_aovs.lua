-- test_aovs.lua: render{aovs = ...} (issue 16 part 2): the light-path AOVs
-- sum to the beauty with glass, mirrors, glossy cones and light that
-- bounces; the beauty keeps its bits; an object matte is exact at pixel
-- coverage; depth, normal, position and albedo against closed forms;
-- regions, saving, and the errors. The EXR layers are read back with
-- OpenEXRCore in tests/c/test_aov.c.
local T = require "harness"
local lancer = require "lancer"

local HERE = "test_aovs.lua:"
local ALL = {'depth', 'normal', 'albedo', 'position', 'object', 'material', 'direct',
             'reflection', 'refraction', 'indirect', 'emission'}
local LIGHT = {'direct', 'reflection', 'refraction', 'indirect', 'emission'}

-- Glass (with a coloured absorption), a mirror, a glossy ball, a glowing
-- ball, a highlight on the floor, ambient light and a sky-coloured background.
local function mixed()
  local s = lancer.scene{camera = lancer.camera{from = {0, 2, -6}, at = {0, 1, 0}, fov = 50},
                         background = {0.1, 0.2, 0.3}, ambient = 0.2}
  s:add(lancer.sphere{center = {0, 1, 0}, radius = 1, material = lancer.material{
    color = {0.95, 0.95, 1}, kd = 0, kt = 0.9, ior = 1.5, absorption = {0.2, 0.1, 0}}})
  s:add(lancer.sphere{center = {2, 1, 1}, radius = 1,
                      material = lancer.material{kd = 0.2, kr = 0.7, ka = 0.1}})
  s:add(lancer.sphere{center = {-2.2, 0.8, 0.5}, radius = 0.8,
                      material = lancer.material{kd = 0.3, kr = 0.6, glossiness = 10,
                                                 cone_samples = 4}})
  s:add(lancer.sphere{center = {-2, 2.5, 2}, radius = 0.5,
                      material = lancer.material{emission = {2, 1.5, 1}}})
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}, material = lancer.material{
    color = {0.8, 0.7, 0.6}, ka = 0.3, ks = 0.3, alpha = 20}})
  s:add(lancer.point_light{position = {2, 4, -3}, intensity = 40})
  return s
end

-- The worst |sum of light AOVs - beauty| / beauty over every channel, and
-- each light AOV's total.
local function split_error(img)
  local L = {}
  for i, n in ipairs(LIGHT) do L[i] = img:aov(n) end
  local worst, totals = 0, {0, 0, 0, 0, 0}
  for y = 1, img.height do
    for x = 1, img.width do
      local b, s = {img:pixel(x, y)}, {0, 0, 0}
      for i, a in ipairs(L) do
        local c = {a:pixel(x, y)}
        for k = 1, 3 do s[k], totals[i] = s[k] + c[k], totals[i] + c[k] end
      end
      for k = 1, 3 do
        local e = math.abs(s[k] - b[k])
        if e > 0 then worst = math.max(worst, e / b[k]) end
      end
    end
  end
  return worst, totals
end

local function same_bits(a, b, what)
  for y = 1, a.height do
    for x = 1, a.width do
      local p, q = {a:pixel(x, y)}, {b:pixel(x, y)}
      for k = 1, 3 do
        if p[k] ~= q[k] then
          error(("%s: pixel (%d, %d) channel %d: %.9g, without AOVs %.9g"):format(
            what, x, y, k, p[k], q[k]), 2)
        end
      end
    end
  end
end

T.test("light AOVs sum to the beauty: glass, mirrors, glossy, emitters, Whitted", function()
  local opts = {width = 40, height = 30, samples = 4, aovs = ALL}
  local img, st = mixed():render(opts)
  T.eq(table.concat(st.aovs, " "), table.concat(ALL, " "), "stats.aovs")
  T.eq(table.concat(img:aovs(), " "), table.concat(ALL, " "), "img:aovs()")
  local worst, totals = split_error(img)
  -- Each AOV is a double sum rounded once to float, the beauty too: five
  -- roundings of at most 2^-24 and the sum's own, relative to the beauty.
  assert(worst <= 6 * 2^-24, ("worst relative error %.3g"):format(worst))
  for i, n in ipairs(LIGHT) do
    if n == "indirect" then T.eq(totals[i], 0, "Whitted's indirect")
    else assert(totals[i] > 0, n .. " holds nothing") end
  end
  assert(lancer.ledger(st):find("\n  aovs      depth, normal, albedo,", 1, true),
         "the ledger lists the AOVs")
  opts.aovs = nil
  local plain, pst = mixed():render(opts)
  same_bits(img, plain, "beauty with AOVs")
  T.eq(#pst.aovs, 0, "a plain render's stats.aovs")
  assert(not lancer.ledger(pst):find("aovs", 1, true), "a plain ledger shows no AOVs")
end)

T.test("light AOVs sum to the beauty with light that bounces (indirect = 3)", function()
  local opts = {width = 32, height = 24, samples = 4, indirect = 3, aovs = LIGHT}
  local img = mixed():render(opts)
  local worst, totals = split_error(img)
  assert(worst <= 6 * 2^-24, ("worst relative error %.3g"):format(worst))
  for i, n in ipairs(LIGHT) do assert(totals[i] > 0, n .. " holds nothing") end
  opts.aovs = nil
  same_bits(img, mixed():render(opts), "path-traced beauty with AOVs")
end)

T.test("a mirror's reflection AOV is kr times what it shows; refraction behind glass", function()
  -- A mirror (kd 0) filling the view shows the background: all of it in
  -- reflection, kr times the background, nothing direct.
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}, fov = 20},
                         background = {0.5, 0.25, 1}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 0.2, 1},
                     material = lancer.material{kd = 0, kr = 0.5}})
  s:add(lancer.point_light{position = {0, 0, 3}, intensity = 1})
  local img = s:render{width = 4, height = 4, aovs = {'reflection', 'direct', 'emission'}}
  local r, g, b = img:aov('reflection'):pixel(2, 2)
  T.eq(r, 0.25, "reflection r"); T.eq(g, 0.125, "reflection g"); T.eq(b, 0.5, "reflection b")
  T.eq((img:aov('direct'):pixel(2, 2)), 0, "direct")
  T.eq((img:aov('emission'):pixel(2, 2)), 0, "emission")
  -- A clear pane (kt 1, ior 1: no Fresnel reflection) in front of the
  -- background: all of it in refraction.
  local p = lancer.scene{camera = lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}, fov = 20},
                         background = {0.5, 0.25, 1}}
  p:add(lancer.box{min = {-5, -5, -1}, max = {5, 5, 0}, material = lancer.material{
    kd = 0, kt = 1, ior = 1}})
  p:add(lancer.point_light{position = {0, 0, 3}, intensity = 1})
  local q = p:render{width = 4, height = 4, aovs = {'refraction', 'emission'}}
  T.eq((q:aov('refraction'):pixel(2, 2)), 0.5, "refraction r")
  T.eq((q:aov('emission'):pixel(2, 2)), 0, "emission behind glass")
  -- The background seen directly is emission.
  local e = p:render{width = 4, height = 4, region = {0, 0, 1, 1}, aovs = {'emission'}}
  T.eq(e.width, 1, "region width")
end)

-- A quad covering x < 0 in front of a camera on the z axis, an odd width so
-- the middle pixel's centre is on the edge: half its samples meet the quad.
local function edge_scene()
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}, fov = 30}}
  local m = lancer.material{color = {0.5, 0.5, 0.5}}
  s:add(lancer.plane{point = {0, 0, -10}, normal = {0, 0, 1}, material = m})  -- id 1
  s:add(lancer.quad{corner = {-10, -10, 0}, u = {10, 0, 0}, v = {0, 20, 0}, material = m})
  s:add(lancer.point_light{position = {0, 0, 5}, intensity = 25})
  return s, s:objects()[2].id
end

T.test("an object matte is exact at pixel coverage: 16 stratified samples, 0.5 on an edge",
       function()
  for _, sampler in ipairs{"sobol", "jitter"} do
    local s, id = edge_scene()
    local img = s:render{width = 9, height = 3, samples = 16, sampler = sampler,
                         aovs = {'object'}}
    local m = img:matte('object', id)
    for x = 1, 9 do
      local want = x < 5 and 1 or x == 5 and 0.5 or 0
      for y = 1, 3 do
        T.eq((m:pixel(x, y)), want, ("%s: matte at (%d, %d)"):format(sampler, x, y))
        T.eq((img:matte('object', 1):pixel(x, y)), 1 - want, sampler .. ": the wall's")
      end
    end
    -- The id most samples see; at the tie, the smaller id (the wall, 1).
    T.eq(id, 2, "the quad's id")
    T.eq((img:aov('object'):pixel(1, 2)), id, "left")
    T.eq((img:aov('object'):pixel(5, 2)), 1, "the tie")
    T.eq((img:aov('object'):pixel(9, 2)), 1, "right")
    T.eq((img:matte('object', 7):pixel(5, 2)), 0, "an id not in the scene")
  end
end)

T.test("the material AOV and matte: 1 + the scene's material index", function()
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}, fov = 30}}
  local a, b = lancer.material{color = {1, 0, 0}}, lancer.material{color = {0, 0, 1}}
  s:add(lancer.plane{point = {0, 0, -10}, normal = {0, 0, 1}, material = a})
  s:add(lancer.quad{corner = {-10, -10, 0}, u = {10, 0, 0}, v = {0, 20, 0}, material = b})
  s:add(lancer.point_light{position = {0, 0, 5}, intensity = 25})
  local img = s:render{width = 9, height = 3, samples = 16, aovs = {'material', 'albedo'}}
  T.eq((img:aov('material'):pixel(1, 1)), 2, "the quad's material")
  T.eq((img:aov('material'):pixel(9, 1)), 1, "the wall's material")
  T.eq((img:matte('material', 2):pixel(5, 2)), 0.5, "half")
  local r, g, bl = img:aov('albedo'):pixel(5, 2)
  T.eq(r, 0.5, "albedo r: the mean of red and blue"); T.eq(bl, 0.5, "albedo b")
  T.eq(g, 0, "albedo g")
end)

T.test("depth, normal and position of a floor against their closed forms", function()
  -- Eye at height h looking along +z: the ray through row y (centre py)
  -- meets the floor at camera depth h / ((2 py / H - 1) ty), ty = tan(fov/2) H / W.
  local h, W, H, fov = 2, 8, 12, 60
  local s = lancer.scene{camera = lancer.camera{from = {0, h, 0}, at = {0, h, 1}, fov = fov}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0},
                     material = lancer.material{color = {0.25, 0.5, 0.75}}})
  s:add(lancer.point_light{position = {0, 5, 5}, intensity = 10})
  local img = s:render{width = W, height = H, aovs = {'depth', 'normal', 'position', 'albedo'}}
  local ty = math.tan(math.rad(fov / 2)) * H / W
  local depth, normal, pos = img:aov('depth'), img:aov('normal'), img:aov('position')
  for y = 1, H do
    local sy = 2 * (y - 0.5) / H - 1
    for x = 1, W do
      local z = depth:pixel(x, y)
      if sy <= 0 then
        T.eq(z, math.huge, ("depth of the sky at (%d, %d)"):format(x, y))
        T.eq((normal:pixel(x, y)), 0, "no normal")
      else
        T.near(z, h / (sy * ty), 4e-7 * z, ("depth at (%d, %d)"):format(x, y))
        local nx, ny, nz = normal:pixel(x, y)
        T.eq(nx, 0, "normal x"); T.eq(ny, 1, "normal y"); T.eq(nz, 0, "normal z")
        local px, py, pz = pos:pixel(x, y)
        T.near(py, 0, 1e-12, "position y")
        T.near(pz, z, 4e-7 * z, "position z: the depth, the camera at z = 0")
        local sx = (2 * (x - 0.5) / W - 1) * math.tan(math.rad(fov / 2))
        T.near(px, -sx * z, 4e-7 * z, "position x")   -- +x is the camera's left
        T.eq((img:aov('albedo'):pixel(x, y)), 0.25, "albedo")
      end
    end
  end
end)

T.test("an AOV of a region is that part of the whole frame's", function()
  local opts = {width = 24, height = 16, samples = 4, aovs = ALL}
  local whole = mixed():render(opts)
  opts.region = {5, 3, 17, 11}
  local part = mixed():render(opts)
  for _, n in ipairs(ALL) do
    local a, b = whole:aov(n), part:aov(n)
    T.eq(b.width, 12, n .. " width")
    T.eq(table.concat(b.region, " "), "5 3 17 11", n .. " region")
    for y = 1, 8 do
      for x = 1, 12 do
        local p, q = {a:pixel(x + 5, y + 3)}, {b:pixel(x, y)}
        for k = 1, 3 do T.eq(q[k], p[k], ("%s (%d, %d)"):format(n, x, y)) end
      end
    end
  end
end)

T.test("PNG saves the beauty alone; EXR saves the layers, or not with aovs = false", function()
  local dir = os.tmpname()
  os.remove(dir)
  assert(os.execute("mkdir -p " .. dir))
  local opts = {width = 16, height = 12, samples = 2}
  local plain = mixed():render(opts)
  opts.aovs = ALL
  local img = mixed():render(opts)
  local function bytes(p) local f = assert(io.open(p, "rb")); local s = f:read("a"); f:close(); return s end
  plain:save(dir .. "/plain.png")
  img:save(dir .. "/aovs.png")
  T.eq(bytes(dir .. "/aovs.png") == bytes(dir .. "/plain.png"), true, "PNG bytes")
  img:save(dir .. "/aovs.exr")
  img:save(dir .. "/beauty.exr", {aovs = false})
  plain:save(dir .. "/plain.exr")
  T.eq(bytes(dir .. "/beauty.exr") == bytes(dir .. "/plain.exr"), true, "EXR without layers")
  assert(#bytes(dir .. "/aovs.exr") > #bytes(dir .. "/plain.exr"), "no layers written")
  local back = lancer.load_exr(dir .. "/aovs.exr")     -- the beauty's R, G, B
  same_bits(back, lancer.load_exr(dir .. "/plain.exr"), "beauty read back")
  img:aov('depth'):save(dir .. "/depth.exr", {pixel = "float"})   -- one AOV alone
  T.eq(lancer.load_exr(dir .. "/depth.exr"):pixel(8, 12), (img:aov('depth'):pixel(8, 12)),
       "depth on its own")
  os.execute("rm -rf " .. dir)
end)

T.test("AOV errors name the field, the name and the line", function()
  local s = mixed()
  T.check_error(function() s:render{width = 4, height = 4, aovs = 'depth'} end,
                HERE, "'render'", "field 'aovs'", "list of AOV names expected, got string")
  T.check_error(function() s:render{width = 4, height = 4, aovs = {'depth', 'dept'}} end,
                HERE, "field 'aovs'", "item 2", "expected one of 'depth', 'normal'", "got 'dept'")
  T.check_error(function() s:render{width = 4, height = 4, aovs = {7}} end,
                HERE, "field 'aovs'", "item 1", "got number")
  T.check_error(function() s:render{width = 4, height = 4, noise = 0.1, aovs = {'depth'}} end,
                HERE, "'render'", "aovs", "adaptive sampling")
  local img = s:render{width = 4, height = 4, aovs = {'depth'}}
  T.eq(#s:render{width = 4, height = 4}:aovs(), 0, "a plain render's aovs")
  T.check_error(function() img:aov('normal') end, HERE, "'aov'", "no normal AOV",
                "aovs = {'normal', ...}")
  T.check_error(function() img:aov('nromal') end, HERE, "'aov'", "got 'nromal'")
  T.check_error(function() img:matte('depth', 1) end, HERE, "'matte'",
                "object or material AOV, not depth")
  T.check_error(function() img:matte('object', 1) end, HERE, "'matte'", "no object AOV")
  T.check_error(function() img:matte('object', 0) end, HERE, "'matte'", "id >= 1")
  T.check_error(function() img:save("/tmp/x.exr", {aovs = 1}) end, HERE, "field 'aovs'",
                "boolean expected")
end)
