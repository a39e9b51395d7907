-- motion.lua: interpolation for animations: lerp, smoothstep, easing curves, keyframes.
-- Pure functions of numbers or vectors ({x, y, z} or any same-length list);
-- a script computes where things are at time t and builds the frame's scene.
-- Arguments are checked as the binding checks its own: a mistake raises
-- "bad argument #n to 'lerp' (...)" at the caller's line.
local M = {}

-- What a wrong value is called in an error: its __name (lancer.Image),
-- else its type; "no value" for nil.
local function typename(x)
  local mt = getmetatable(x)
  if type(mt) == "table" and type(mt.__name) == "string" then return mt.__name end
  return x == nil and "no value" or type(x)
end

-- Raises "bad argument #arg to 'fn' (msg)" at `level` as error() counts
-- it from the function calling argerror.
local function argerror(level, arg, fn, msg)
  error(("bad argument #%d to '%s' (%s)"):format(arg, fn, msg), level + 1)
end

local function check_number(level, x, arg, fn)
  if type(x) ~= "number" then
    argerror(level + 1, arg, fn, "number expected, got " .. typename(x))
  end
end

-- Why a and b are not both numbers or both lists of numbers of one
-- length: nil, or which is at fault (1: a, 2: b) and what is wrong; `as`
-- names a in b's message ("#1", "key 1's").
local function mismatch(a, b, as)
  if type(a) == "number" then
    if type(b) == "number" then return nil end
    return 2, ("number expected (as %s), got %s"):format(as, typename(b))
  end
  if type(a) ~= "table" then
    return 1, "number or list of numbers expected, got " .. typename(a)
  end
  for i = 1, #a do
    if type(a[i]) ~= "number" then
      return 1, ("component %d: number expected, got %s"):format(i, typename(a[i]))
    end
  end
  local list = ("list of %d number%s"):format(#a, #a == 1 and "" or "s")
  if type(b) ~= "table" then
    return 2, ("%s expected (as %s), got %s"):format(list, as, typename(b))
  end
  if #b ~= #a then
    return 2, ("%s expected (as %s), got a list of %d"):format(list, as, #b)
  end
  for i = 1, #b do
    if type(b[i]) ~= "number" then
      return 2, ("component %d: number expected, got %s"):format(i, typename(b[i]))
    end
  end
end

-- (1 - t) a + t b, of numbers or of lists already checked.
local function mix(a, b, t)
  if type(a) == "number" then return (1 - t) * a + t * b end
  local r = {}
  for i = 1, #a do r[i] = (1 - t) * a[i] + t * b[i] end
  return r
end

-- lerp(a, b, t) = a + (b - a) t for numbers or lists of numbers (per
-- component); exact at t = 0 and t = 1: (1 - t) a + t b.
function M.lerp(a, b, t)
  local which, why = mismatch(a, b, "#1")
  if which then argerror(2, which, "lerp", why) end
  check_number(2, t, 3, "lerp")
  return mix(a, b, t)
end

local function clamp01(t) return t < 0 and 0 or t > 1 and 1 or t end

local function smooth(e0, e1, x)
  local u = clamp01((x - e0) / (e1 - e0))
  return u * u * (3 - 2 * u)
end

-- smoothstep(e0, e1, x): 0 below e0, 1 above e1, 3u^2 - 2u^3 between.
-- smoothstep(x) alone takes e0 = 0, e1 = 1.
function M.smoothstep(...)
  local n, e0, e1, x = select("#", ...), ...
  if n == 1 then
    check_number(2, e0, 1, "smoothstep")
    return smooth(0, 1, e0)
  end
  check_number(2, e0, 1, "smoothstep")
  check_number(2, e1, 2, "smoothstep")
  check_number(2, x, 3, "smoothstep")
  if not (e1 > e0) then
    argerror(2, 2, "smoothstep", ("must be > edge0, got %g <= %g"):format(e1, e0))
  end
  return smooth(e0, e1, x)
end

-- Easing curves: functions of t in [0, 1] (clamped) with f(0) = 0, f(1) = 1,
-- all monotonic. Each checks its argument under its own name.
local CURVES = {
  linear = function(t) return t end,
  smoothstep = function(t) return smooth(0, 1, t) end,
  in_quad = function(t) return t * t end,
  out_quad = function(t) return t * (2 - t) end,
  in_out_quad = function(t)
    return t < 0.5 and 2 * t * t or 1 - 2 * (1 - t) * (1 - t)
  end,
  in_cubic = function(t) return t * t * t end,
  out_cubic = function(t) t = 1 - t return 1 - t * t * t end,
  in_out_cubic = function(t) return t < 0.5 and 4 * t * t * t or 1 - 4 * (1 - t) ^ 3 end,
  in_out_sine = function(t) return (1 - math.cos(math.pi * t)) / 2 end,
}
CURVES.ease_in, CURVES.ease_out, CURVES.ease_in_out =
  CURVES.in_cubic, CURVES.out_cubic, CURVES.in_out_cubic
M.ease = {}
for name, f in pairs(CURVES) do
  local fn = "ease." .. name
  M.ease[name] = function(t)
    check_number(2, t, 1, fn)
    return f(clamp01(t))
  end
end

-- lerp_angle(a, b, t): degrees, along the shorter way round (350 -> 10 goes
-- through 0, not back through 180).
function M.lerp_angle(a, b, t)
  check_number(2, a, 1, "lerp_angle")
  check_number(2, b, 2, "lerp_angle")
  check_number(2, t, 3, "lerp_angle")
  local d = (b - a) % 360
  if d > 180 then d = d - 360 end
  return a + d * t
end

-- keyframes{{t0, v0}, {t1, v1, "ease_in_out"}, ...}: a function of time.
-- Times must increase; values are numbers or lists of numbers, all of the
-- first key's kind and length; the easing named on a key (a name in
-- lancer.ease or a function) shapes the segment arriving there. Before the
-- first key: v0; after the last: the last value.
function M.keyframes(keys)
  local function bad(msg) argerror(3, 1, "keyframes", msg) end
  if type(keys) ~= "table" or #keys == 0 then
    bad("non-empty list of {time, value [, easing]} expected, got " ..
        (type(keys) == "table" and "an empty table" or typename(keys)))
  end
  local ks = {}
  for i, k in ipairs(keys) do
    if type(k) ~= "table" or type(k[1]) ~= "number" or k[2] == nil then
      bad(("key %d: {time, value [, easing]} expected"):format(i))
    end
    if k[1] ~= k[1] or k[1] == math.huge or k[1] == -math.huge then
      bad(("key %d: time must be finite, got %s"):format(i, tostring(k[1])))
    end
    local which, why = mismatch(i == 1 and k[2] or ks[1].v, k[2], "key 1's")
    if which then bad(("key %d: value: %s"):format(i, why)) end
    local ease = k[3] or "linear"
    if type(ease) == "string" then
      local f = M.ease[ease]
      if not f then
        local names = {}
        for n in pairs(M.ease) do names[#names + 1] = n end
        table.sort(names)
        bad(("key %d: unknown easing '%s'; one of %s"):format(i, ease,
            table.concat(names, ", ")))
      end
      ease = f
    elseif type(ease) ~= "function" then
      bad(("key %d: easing name or function expected, got %s"):format(i, typename(ease)))
    end
    if i > 1 and not (k[1] > ks[i - 1].t) then
      bad(("key %d: times must increase, got %g after %g"):format(i, k[1], ks[i - 1].t))
    end
    ks[i] = {t = k[1], v = k[2], ease = ease}
  end
  return function(t)
    check_number(2, t, 1, "keyframes curve")
    if t <= ks[1].t then return ks[1].v end
    for i = 2, #ks do
      local b = ks[i]
      if t <= b.t then
        local a = ks[i - 1]
        if t == b.t then return b.v end
        local u = b.ease((t - a.t) / (b.t - a.t))
        if type(u) ~= "number" then
          error(("keyframes curve: key %d's easing returned %s, number expected"):format(
            i, typename(u)), 2)
        end
        return mix(a.v, b.v, u)
      end
    end
    return ks[#ks].v
  end
end

return M
