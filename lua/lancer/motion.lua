-- motion.lua: interpolation for animations: lerp, smoothstep, easing curves, keyframes.
-- Pure functions of numbers or vectors ({x, y, z} or any same-length list);
-- a script computes where things are at time t and builds the frame's scene.
local M = {}

local function check_number(x, arg, fn)
  if type(x) ~= "number" then
    error(("bad argument #%d to '%s' (number expected, got %s)"):format(arg, fn, type(x)), 3)
  end
end

-- lerp(a, b, t) = a + (b - a) t for numbers or lists of numbers (per
-- component); exact at t = 0 and t = 1: (1 - t) a + t b.
function M.lerp(a, b, t)
  check_number(t, 3, "lerp")
  if type(a) == "number" and type(b) == "number" then
    return (1 - t) * a + t * b
  end
  if type(a) ~= "table" or type(b) ~= "table" or #a ~= #b then
    error("bad argument to 'lerp' (two numbers or two lists of the same length expected)", 2)
  end
  local r = {}
  for i = 1, #a do r[i] = (1 - t) * a[i] + t * b[i] end
  return r
end

local function clamp01(t) return t < 0 and 0 or t > 1 and 1 or t end

-- smoothstep(e0, e1, x): 0 below e0, 1 above e1, 3u^2 - 2u^3 between.
-- smoothstep(x) alone takes e0 = 0, e1 = 1.
function M.smoothstep(e0, e1, x)
  if x == nil then e0, e1, x = 0, 1, e0 end
  check_number(x, 3, "smoothstep")
  if not (e1 > e0) then
    error(("bad argument #2 to 'smoothstep' (must be > edge0, got %g <= %g)"):format(e1, e0), 2)
  end
  local u = clamp01((x - e0) / (e1 - e0))
  return u * u * (3 - 2 * u)
end

-- Easing curves: functions of t in [0, 1] (clamped) with f(0) = 0, f(1) = 1,
-- all monotonic.
M.ease = {
  linear = function(t) return clamp01(t) end,
  smoothstep = function(t) return M.smoothstep(t) end,
  in_quad = function(t) t = clamp01(t) return t * t end,
  out_quad = function(t) t = clamp01(t) return t * (2 - t) end,
  in_out_quad = function(t)
    t = clamp01(t)
    return t < 0.5 and 2 * t * t or 1 - 2 * (1 - t) * (1 - t)
  end,
  in_cubic = function(t) t = clamp01(t) return t * t * t end,
  out_cubic = function(t) t = 1 - clamp01(t) return 1 - t * t * t end,
  in_out_cubic = function(t)
    t = clamp01(t)
    return t < 0.5 and 4 * t * t * t or 1 - 4 * (1 - t) ^ 3
  end,
  in_out_sine = function(t) return (1 - math.cos(math.pi * clamp01(t))) / 2 end,
}
M.ease.ease_in = M.ease.in_cubic
M.ease.ease_out = M.ease.out_cubic
M.ease.ease_in_out = M.ease.in_out_cubic

-- lerp_angle(a, b, t): degrees, along the shorter way round (350 -> 10 goes
-- through 0, not back through 180).
function M.lerp_angle(a, b, t)
  check_number(a, 1, "lerp_angle")
  check_number(b, 2, "lerp_angle")
  check_number(t, 3, "lerp_angle")
  local d = (b - a) % 360
  if d > 180 then d = d - 360 end
  return a + d * t
end

-- keyframes{{t0, v0}, {t1, v1, "ease_in_out"}, ...}: a function of time.
-- Times must increase; values are numbers or lists; the easing named on a
-- key (a name in lancer.ease or a function) shapes the segment arriving
-- there. Before the first key: v0; after the last: the last value.
function M.keyframes(keys)
  if type(keys) ~= "table" or #keys == 0 then
    error("bad argument #1 to 'keyframes' (non-empty list of {time, value [, easing]} expected)", 2)
  end
  local ks = {}
  for i, k in ipairs(keys) do
    if type(k) ~= "table" or type(k[1]) ~= "number" or k[2] == nil then
      error(("bad argument #1 to 'keyframes' (key %d: {time, value [, easing]} expected)"):format(i), 2)
    end
    local ease = k[3] or "linear"
    if type(ease) == "string" then
      local f = M.ease[ease]
      if not f then
        local names = {}
        for n in pairs(M.ease) do names[#names + 1] = n end
        table.sort(names)
        error(("bad argument #1 to 'keyframes' (key %d: unknown easing '%s'; one of %s)")
              :format(i, ease, table.concat(names, ", ")), 2)
      end
      ease = f
    elseif type(ease) ~= "function" then
      error(("bad argument #1 to 'keyframes' (key %d: easing name or function expected)"):format(i), 2)
    end
    if i > 1 and not (k[1] > ks[i - 1].t) then
      error(("bad argument #1 to 'keyframes' (key %d: times must increase, got %g after %g)")
            :format(i, k[1], ks[i - 1].t), 2)
    end
    ks[i] = {t = k[1], v = k[2], ease = ease}
  end
  return function(t)
    if t <= ks[1].t then return ks[1].v end
    for i = 2, #ks do
      local b = ks[i]
      if t <= b.t then
        local a = ks[i - 1]
        if t == b.t then return b.v end
        return M.lerp(a.v, b.v, b.ease((t - a.t) / (b.t - a.t)))
      end
    end
    return ks[#ks].v
  end
end

return M
