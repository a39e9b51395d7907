-- cornell.lua: the Cornell box (scenes/cornell.lua) against POV-Ray 3.7's
-- radiosity, by time to a stated error.
--
-- Radiosity (an irradiance cache over a pretrace) and path tracing are
-- different estimators: one is biased and smooth, the other unbiased and
-- noisy, so their times at equal settings say nothing. Both are measured
-- against lancer's converged image (cached in out/bench/), each at a sweep
-- of its own quality knob (POV-Ray: radiosity count and error_bound;
-- lancer: samples per pixel), and the time each needs to reach the target
-- RMSE is read off its curve, interpolated in log-log.
--
-- The POV-Ray file is written from the box's numbers so that both images
-- show the same thing: the camera (POV-Ray's own cornell.pov's), linear
-- reflectances as POV-Ray pigments with `diffuse 1` (POV-Ray's diffuse
-- term has no 1/pi: kd C Lc cos, the same as lancer's Lambert for a light
-- colour Lc), and the emitting quad as an area light whose samples fall off
-- as an emitting patch does: `spotlight ... tightness 1` is the cosine at
-- the emitter, `fade_power 2` with a tiny fade_distance d is 2 d^2 / r^2,
-- `area_illumination on` evaluates both at every sample, so a light colour
-- of L A / (2 pi d^2) gives each point the irradiance of a patch of
-- radiance L and area A (checked against lancer's indirect = 0 image:
-- walls within 0.2 %). The patch itself is an `emission` box that casts no
-- shadow and that radiosity rays do not see (the light is already the
-- light source's). Images are compared as linear 16-bit PNGs, the light
-- and the pixels next to it left out (it is 17 times brighter than the
-- walls, and a 16-bit PNG clips it).
local M = {}

local fmt = string.format

local function vec(v) return fmt("<%.10g, %.10g, %.10g>", v[1], v[2], v[3]) end

M.FADE = 0.1             -- fade_distance: 2 / (1 + (r/d)^2) is 2 d^2 / r^2 within 0.003 % at r >= 20

-- Writes the box as a POV-Ray file. o: {count, error_bound, nearest_count,
-- recursion_limit, pretrace_end, area (light samples per side)}; count nil
-- leaves radiosity off (direct light only).
function M.write_pov(box, path, o)
  local f = assert(io.open(path .. ".tmp", "w"))
  f:write("// The Cornell box (lancer's scenes/cornell.lua), written by tools/bench/cornell.lua\n")
  f:write("#version 3.7;\n")
  f:write("global_settings { assumed_gamma 1.0 max_trace_level 10 adc_bailout 0 " ..
          "ambient_light 0\n")
  if o.count then
    f:write(fmt("  radiosity { pretrace_start 0.08 pretrace_end %.10g count %d " ..
                "nearest_count %d error_bound %.10g recursion_limit %d " ..
                "low_error_factor 0.5 gray_threshold 0 minimum_reuse 0.015 brightness 1 " ..
                "adc_bailout 0.001 }\n", o.pretrace_end or 0.01, o.count,
                o.nearest_count or 10, o.error_bound or 0.5, o.recursion_limit or 3))
  end
  f:write("}\n")
  local c = box.camera
  -- POV-Ray's cornell.pov camera: right -x makes it right-handed, as lancer's.
  f:write(fmt("camera { location %s direction <0, 0, 1> up <0, 1, 0> right <-1, 0, 0> " ..
              "angle %.10g look_at %s }\n", vec(c.from), c.fov, vec(c.at)))
  local L = box.light
  local area = math.sqrt((L.u[2] * L.v[3] - L.u[3] * L.v[2]) ^ 2 +
                         (L.u[3] * L.v[1] - L.u[1] * L.v[3]) ^ 2 +
                         (L.u[1] * L.v[2] - L.u[2] * L.v[1]) ^ 2)
  -- k x k lights, each an n x n area light over its part of the quad:
  -- POV-Ray 3.7 sums area_illumination's samples with their cosines
  -- unclamped, so a face whose plane cuts the light (the tall block's
  -- front) is darkened by the samples behind it (measured: 0.63 of the
  -- closed form with one 16 x 16 light); small parts keep that to the
  -- one part the plane cuts.
  local k, n = o.parts or 8, o.area or 2
  local scale = area / (2 * math.pi * M.FADE ^ 2) / (k * k)
  local du, dv = {}, {}
  for c = 1, 3 do du[c], dv[c] = L.u[c] / k, L.v[c] / k end
  for i = 0, k - 1 do
    for j = 0, k - 1 do
      local p = {}
      for c = 1, 3 do p[c] = L.corner[c] + (i + 0.5) * du[c] + (j + 0.5) * dv[c] end
      f:write(fmt("light_source { %s color rgb %s\n  area_light %s, %s, %d, %d %s %s " ..
                  "area_illumination on\n  spotlight radius -90 falloff 90 tightness 1 " ..
                  "point_at %s\n  fade_power 2 fade_distance %.10g }\n", vec(p),
                  vec{L.radiance[1] * scale, L.radiance[2] * scale, L.radiance[3] * scale},
                  vec(du), vec(dv), n, n, o.jitter == false and "" or "jitter",
                  o.adaptive and ("adaptive " .. o.adaptive) or "",
                  vec{p[1], p[2] - 1, p[3]}, M.FADE))
    end
  end
  local far = {L.corner[1] + L.u[1] + L.v[1], L.corner[2] + 0.01,
               L.corner[3] + L.u[3] + L.v[3]}
  f:write(fmt("box { %s, %s no_shadow no_radiosity pigment { rgb 1 } " ..
              "finish { emission rgb %s diffuse 0 ambient 0 } }\n", vec(L.corner), vec(far),
              vec(L.radiance)))
  local function mesh(vertices, faces, color)
    f:write("union {\n")
    for _, face in ipairs(faces) do
      for k = 2, #face - 1 do            -- a fan of triangles, as lancer's mesh splits them
        f:write(fmt("  triangle { %s, %s, %s }\n", vec(vertices[face[1]]),
                    vec(vertices[face[k]]), vec(vertices[face[k + 1]])))
      end
    end
    f:write(fmt("  texture { pigment { rgb %s } finish { diffuse 1 ambient 0 } }\n}\n",
                vec(box.colors[color])))
  end
  for _, w in ipairs(box.walls) do mesh(w.vertices, w.faces, w.color) end
  for _, b in ipairs(box.blocks) do
    local v, fs = box.block_mesh(b)
    mesh(v, fs, "white")
  end
  assert(f:close())
  assert(os.rename(path .. ".tmp", path))
end


M.SIDE = 128                       -- pixels a side, both renderers
M.REF_INDIRECT = 64                -- bounces in the reference: 0.725^64 of the light is left
M.REF_HALF = 2048                  -- samples in each of the reference's two halves

local function read_all(path)
  local f = io.open(path, "rb")
  if not f then return nil end
  local s = f:read("a")
  f:close()
  return s
end

-- The converged reference: two renders of REF_HALF samples with seeds of
-- their own, averaged, and its own standard error per channel (RMS over
-- pixels) from their difference. Cached in dir as an EXR, under a key
-- made of what decides it (the scene file and the path tracer's source,
-- hashed, and the settings): a bench run after the first reads it back.
function M.reference(ctx)
  local lancer = require "lancer"
  local hash = ctx.run.output(("cd %s && cat scenes/cornell.lua src/render/path.c src/material/bsdf.h src/light/*.h" ..
                               " | sha1sum"):format(ctx.run.quote(ctx.root))) or "?"
  local key = ("%s side=%d indirect=%d half=%d"):format(hash:match("^%x+") or "?", M.SIDE,
                                                       M.REF_INDIRECT, M.REF_HALF)
  local exr, keyfile = ctx.out .. "/cornell-ref.exr", ctx.out .. "/cornell-ref.key"
  local cached = read_all(keyfile)
  if cached and cached:match("^[^\n]*") == key then
    local ok, img = pcall(lancer.load_exr, exr)
    if ok then
      ctx.say("  reference: cached %s", exr:sub(#ctx.root + 2))
      return img, tonumber(cached:match("\nsigma=([%d.e+-]+)")), tonumber(
        cached:match("\nseconds=([%d.e+-]+)"))
    end
  end
  local scene = assert(loadfile(ctx.root .. "/scenes/cornell.lua"))("--scene")
  ctx.say("  reference: %dx%d, indirect %d, 2 x %d samples (a few minutes, once)", M.SIDE,
          M.SIDE, M.REF_INDIRECT, M.REF_HALF)
  local o = {width = M.SIDE, height = M.SIDE, samples = M.REF_HALF,
             indirect = M.REF_INDIRECT, seed = 424242, progress = false}
  local a, st = scene:render(o)
  o.seed = 424243
  local b, st2 = scene:render(o)
  local sigma = math.sqrt(a:error(b).mse / 4)        -- the average's standard error
  local ref = lancer.image{width = M.SIDE, height = M.SIDE}:add(a, 0.5):add(b, 0.5)
  ref:save(exr)
  local f = assert(io.open(keyfile, "w"))
  f:write(key, ("\nsigma=%.6g\nseconds=%.3f\n"):format(sigma, st.seconds + st2.seconds))
  f:close()
  return ref, sigma, st.seconds + st2.seconds
end

-- Pixels compared: all but the light and the pixels beside it (where the
-- reference has a channel over 1).
local function mask_of(ref)
  local w, h, bright, keep = ref.width, ref.height, {}, {}
  for y = 1, h do
    for x = 1, w do
      local r, g, b = ref:pixel(x, y)
      bright[(y - 1) * w + x] = math.max(r, g, b) > 1
    end
  end
  for y = 1, h do
    for x = 1, w do
      local ok = true
      for dy = -1, 1 do
        for dx = -1, 1 do
          local u, v = x + dx, y + dy
          if u >= 1 and u <= w and v >= 1 and v <= h and bright[(v - 1) * w + u] then
            ok = false
          end
        end
      end
      keep[(y - 1) * w + x] = ok
    end
  end
  return keep
end

-- RMSE and mean bias over the kept pixels, on linear values, every channel.
local function rmse(img, ref, keep)
  local s, d, n = 0, 0, 0
  for y = 1, ref.height do
    for x = 1, ref.width do
      if keep[(y - 1) * ref.width + x] then
        local a1, a2, a3 = img:pixel(x, y)
        local b1, b2, b3 = ref:pixel(x, y)
        s = s + (a1 - b1) ^ 2 + (a2 - b2) ^ 2 + (a3 - b3) ^ 2
        d = d + (a1 - b1) + (a2 - b2) + (a3 - b3)
        n = n + 3
      end
    end
  end
  return math.sqrt(s / n), d / n
end

-- The time at which a curve of {seconds, rmse} points (in the order of
-- rising cost) first reaches target, interpolated in log-log between the
-- points around it; nil and the best point when it never does.
function M.time_to(points, target)
  for i, p in ipairs(points) do
    if p.rmse <= target then
      if i == 1 then return p.seconds, "at or under the cheapest setting" end
      local q = points[i - 1]
      local t = (math.log(target) - math.log(q.rmse)) / (math.log(p.rmse) - math.log(q.rmse))
      return math.exp(math.log(q.seconds) + t * (math.log(p.seconds) - math.log(q.seconds)))
    end
  end
  return nil
end

M.TARGET = 0.005                   -- RMSE, linear: about 1.3/255 on these walls
-- POV-Ray's sweep: radiosity count and error_bound together (the cache's
-- density and how far a sample is reused), nearest_count 10 and
-- more bounces (recursion_limit) as the count grows.
-- The light: 4 x 4 parts of 2 x 2 jittered samples (64 shadow rays a
-- point); 8 x 8 parts took 4 times as long for the same error here.
M.POV_LEVELS = {
  {count = 20, error_bound = 1.8, recursion_limit = 1},
  {count = 50, error_bound = 1.0, recursion_limit = 2},
  {count = 100, error_bound = 0.5, recursion_limit = 3},
  {count = 200, error_bound = 0.5, recursion_limit = 5},
}
M.POV_LIGHT = {parts = 4, area = 2}
M.LANCER_SAMPLES = {4, 16, 64, 256}
M.LANCER_INDIRECT = 16

-- ctx: {run, runstat, root, out, say, quick}. Returns the Markdown section.
function M.section(ctx)
  local lancer = require "lancer"
  local run, say = ctx.run, ctx.say
  local box = assert(loadfile(ctx.root .. "/scenes/cornell.lua"))("--data")
  local ref, sigma, ref_seconds = M.reference(ctx)
  local keep = mask_of(ref)
  local lines = {"## Cornell box: lancer's paths against POV-Ray's radiosity (time to error)\n\n"}
  local function add(f, ...) lines[#lines + 1] = fmt(f, ...) end
  add("scenes/cornell.lua at %dx%d; both against lancer's converged image (indirect %d, " ..
      "2 x %d samples, its own standard error %.5f; cached in out/bench/, made in %.0f s). " ..
      "RMSE on linear values over every channel, the light and the pixels beside it " ..
      "left out. Target RMSE %.3g.\n\n", M.SIDE, M.SIDE, M.REF_INDIRECT, M.REF_HALF,
      sigma or 0, ref_seconds or 0, M.TARGET)
  add("| renderer | setting | seconds | RMSE | mean bias |\n| --- | --- | --- | --- | --- |\n")
  local pov_points, lancer_points = {}, {}
  if run.available("povray") then
    for i, o in ipairs(M.POV_LEVELS) do
      if not (ctx.quick and i > 3) then
        local name = ("cornell-%d"):format(i)
        for k, v in pairs(M.POV_LIGHT) do o[k] = v end
        M.write_pov(box, ("%s/%s.pov"):format(ctx.out, name), o)
        local cmd = {"povray", "+I" .. name .. ".pov", "+O" .. name .. ".png", "+W" .. M.SIDE,
                     "+H" .. M.SIDE, "+FN16", "-D", "+WT" .. (ctx.threads or 2),
                     "File_Gamma=1.0", "-P", "+A0.0", "+AM1", "+R3", "+J0"}
        local r = run.measure(ctx.runstat, cmd, ctx.out, ("%s/%s.log"):format(ctx.out, name))
        if r.wall and r.status == 0 then
          local img = lancer.load_png(("%s/%s.png"):format(ctx.out, name), {encoding = "linear"})
          local e, bias = rmse(img, ref, keep)
          local setting = fmt("count %d, error_bound %g, recursion_limit %d", o.count,
                              o.error_bound, o.recursion_limit)
          pov_points[#pov_points + 1] = {seconds = r.wall, rmse = e}
          add("| POV-Ray 3.7 radiosity | %s | %.2f | %.5f | %+.5f |\n", setting, r.wall, e,
              bias)
          say("  povray %s: %.2f s, RMSE %.5f", setting, r.wall, e)
        else
          say("  povray failed (status %s): %s", tostring(r.status), run.tail(r.log or "", 5))
        end
      end
    end
  else
    add("| POV-Ray 3.7 | missing (apt-get install povray) | - | - | - |\n")
  end
  local scene = assert(loadfile(ctx.root .. "/scenes/cornell.lua"))("--scene")
  for _, spp in ipairs(M.LANCER_SAMPLES) do
    local img, st = scene:render{width = M.SIDE, height = M.SIDE, samples = spp,
                                 indirect = M.LANCER_INDIRECT, seed = 7, progress = false}
    local e, bias = rmse(img, ref, keep)
    lancer_points[#lancer_points + 1] = {seconds = st.seconds, rmse = e}
    add("| lancer paths | %d samples, indirect %d | %.2f | %.5f | %+.5f |\n", spp,
        M.LANCER_INDIRECT, st.seconds, e, bias)
    say("  lancer %d samples: %.2f s, RMSE %.5f", spp, st.seconds, e)
  end
  local tl, tp = M.time_to(lancer_points, M.TARGET), M.time_to(pov_points, M.TARGET)
  local function cell(t, pts)
    if t then return fmt("%.2f s", t) end
    if #pts == 0 then return "not measured" end
    local best = pts[1]
    for _, p in ipairs(pts) do if p.rmse < best.rmse then best = p end end
    return fmt("not reached (best RMSE %.5f at %.2f s)", best.rmse, best.seconds)
  end
  add("\nTime to RMSE %.3g (log-log interpolation between the settings around it): " ..
      "lancer %s, POV-Ray %s%s.\n", M.TARGET, cell(tl, lancer_points), cell(tp, pov_points),
      (tl and tp) and fmt(" (lancer / POV-Ray %.2fx)", tl / tp) or "")
  add("Seconds: POV-Ray's whole process (lc-runstat wall; its 3x3 anti-aliasing grid, " ..
      "+A0.0 +AM1 +R3, as lancer's pixels are box-filtered); lancer's render (stats.seconds, " ..
      "BVH build included), in this process, %d threads both.\n", ctx.threads or 2)
  return table.concat(lines)
end

return M
