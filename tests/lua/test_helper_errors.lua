-- test_helper_errors.lua: the pure-Lua helpers (lua/lancer/*.lua) check
-- their arguments as the binding does: each rule raises "bad argument #n
-- to 'name' (...)" at the caller's line (this file's), never an internal
-- error from inside the helper.
local T = require "harness"
local lancer = require "lancer"

local HERE = "test_helper_errors.lua:"
local check = T.check_error

-- ---- lerp, smoothstep, easing, lerp_angle ------------------------------------

T.test("lerp: t must be a number", function()
  check(function() lancer.lerp(0, 1, "x") end, HERE,
        "bad argument #3 to 'lerp' (number expected, got string)")
  check(function() lancer.lerp(0, 1) end, HERE,
        "#3 to 'lerp' (number expected, got no value)")
end)

T.test("lerp: a must be a number or a list of numbers", function()
  check(function() lancer.lerp("a", 1, 0) end, HERE,
        "bad argument #1 to 'lerp' (number or list of numbers expected, got string)")
  check(function() lancer.lerp({1, "x", 3}, {1, 2, 3}, 0.5) end, HERE,
        "bad argument #1 to 'lerp' (component 2: number expected, got string)")
end)

T.test("lerp: b must be of a's kind and length", function()
  check(function() lancer.lerp(1, {2}, 0.5) end, HERE,
        "bad argument #2 to 'lerp' (number expected (as #1), got table)")
  check(function() lancer.lerp({1}, 2, 0.5) end, HERE,
        "bad argument #2 to 'lerp' (list of 1 number expected (as #1), got number)")
  check(function() lancer.lerp({1, 2, 3}, {1, 2}, 0.5) end, HERE,
        "#2 to 'lerp' (list of 3 numbers expected (as #1), got a list of 2)")
  check(function() lancer.lerp({1, 2}, {1, false}, 0.5) end, HERE,
        "bad argument #2 to 'lerp' (component 2: number expected, got boolean)")
end)

T.test("smoothstep: every argument a number, one or three of them", function()
  check(function() lancer.smoothstep("x") end, HERE,
        "bad argument #1 to 'smoothstep' (number expected, got string)")
  check(function() lancer.smoothstep(0, "1", 0.5) end, HERE,
        "bad argument #2 to 'smoothstep' (number expected, got string)")
  check(function() lancer.smoothstep(0, 1) end, HERE,
        "bad argument #3 to 'smoothstep' (number expected, got no value)")
end)

T.test("smoothstep: edge1 must be above edge0", function()
  check(function() lancer.smoothstep(2, 1, 0.5) end, HERE,
        "bad argument #2 to 'smoothstep' (must be > edge0, got 1 <= 2)")
end)

T.test("easing curves: t must be a number, named in the message", function()
  check(function() lancer.ease.in_quad("x") end, HERE,
        "bad argument #1 to 'ease.in_quad' (number expected, got string)")
  check(function() lancer.ease.ease_in() end, HERE,
        "bad argument #1 to 'ease.ease_in' (number expected, got no value)")
end)

T.test("lerp_angle: every argument a number", function()
  check(function() lancer.lerp_angle(0, "x", 0.5) end, HERE,
        "bad argument #2 to 'lerp_angle' (number expected, got string)")
end)

-- ---- keyframes --------------------------------------------------------------------

T.test("keyframes: a non-empty list of keys", function()
  check(function() lancer.keyframes() end, HERE, "bad argument #1 to 'keyframes' " ..
        "(non-empty list of {time, value [, easing]} expected, got no value)")
  check(function() lancer.keyframes{} end, HERE, "got an empty table")
end)

T.test("keyframes: each key {time, value [, easing]}", function()
  check(function() lancer.keyframes{{0, 1}, {1}} end, HERE,
        "bad argument #1 to 'keyframes' (key 2: {time, value [, easing]} expected)")
end)

T.test("keyframes: times finite and increasing", function()
  check(function() lancer.keyframes{{0 / 0, 1}} end, HERE,
        "bad argument #1 to 'keyframes' (key 1: time must be finite, got ")
  check(function() lancer.keyframes{{0, 1}, {math.huge, 2}} end, HERE,
        "(key 2: time must be finite, got inf)")
  check(function() lancer.keyframes{{0, 1}, {0, 2}} end, HERE,
        "(key 2: times must increase, got 0 after 0)")
end)

T.test("keyframes: an easing is a known name or a function", function()
  check(function() lancer.keyframes{{0, 1}, {1, 2, "bounce"}} end, HERE,
        "bad argument #1 to 'keyframes' (key 2: unknown easing 'bounce'; one of ")
  check(function() lancer.keyframes{{0, 1}, {1, 2, 5}} end, HERE,
        "(key 2: easing name or function expected, got number)")
end)

T.test("keyframes: values numbers or lists, all of the first key's kind", function()
  check(function() lancer.keyframes{{0, "a"}} end, HERE, "bad argument #1 to " ..
        "'keyframes' (key 1: value: number or list of numbers expected, got string)")
  check(function() lancer.keyframes{{0, {0, 0, "z"}}} end, HERE,
        "(key 1: value: component 3: number expected, got string)")
  check(function() lancer.keyframes{{0, {0, 0, 0}}, {1, 5}} end, HERE,
        "(key 2: value: list of 3 numbers expected (as key 1's), got number)")
  check(function() lancer.keyframes{{0, 0}, {1, 2}, {2, {1}}} end, HERE,
        "(key 3: value: number expected (as key 1's), got table)")
end)

T.test("a keyframes curve: its time must be a number", function()
  local f = lancer.keyframes{{0, 0}, {1, 10}}
  check(function() f("x") end, HERE,
        "bad argument #1 to 'keyframes curve' (number expected, got string)")
end)

T.test("a keyframes curve: an easing function must return a number", function()
  local f = lancer.keyframes{{0, 0}, {1, 10, function() return "half" end}}
  T.eq(f(0), 0, "at the first key")
  check(function() f(0.5) end, HERE,
        "keyframes curve: key 2's easing returned string, number expected")
end)

-- ---- ledger -------------------------------------------------------------------

local function stats()
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, 5}, at = {0, 0, 0}}}
  s:add(lancer.sphere{center = {0, 0, 0}, radius = 4},
        lancer.point_light{position = {0, 0, 4.5}, intensity = 1})
  local _, st = s:render{width = 2, height = 2}
  return st
end

T.test("ledger: the statistics table of a render, a string label", function()
  T.has(lancer.ledger(stats(), "frame 1"), "frame 1: ")
  check(function() lancer.ledger() end, HERE, "bad argument #1 to 'ledger' " ..
        "(statistics table of a render expected, got no value)")
  check(function() lancer.ledger(stats(), 5) end, HERE,
        "bad argument #2 to 'ledger' (string expected, got number)")
end)

T.test("ledger: counts are integers, times numbers", function()
  local st = stats()
  st.threads = 1.5
  check(function() lancer.ledger(st) end, HERE,
        "bad argument #1 to 'ledger' (field 'threads': integer expected, got 1.5)")
  st = stats()
  st.seconds = nil
  check(function() lancer.ledger(st) end, HERE,
        "(field 'seconds': number expected, got no value)")
  st = stats()
  st.rays.camera = "many"
  check(function() lancer.ledger(st) end, HERE,
        "(field 'rays.camera': integer expected, got string)")
end)

T.test("ledger: rays and effects are tables", function()
  local st = stats()
  st.rays = 7
  check(function() lancer.ledger(st) end, HERE,
        "bad argument #1 to 'ledger' (field 'rays': table expected, got number)")
  st = stats()
  st.effects = nil
  check(function() lancer.ledger(st) end, HERE,
        "(field 'effects': table expected, got no value)")
end)

-- ---- the prompt's show ------------------------------------------------------------

T.test("show: a live lancer.Image", function()
  local repl = require "lancer.repl"
  check(function() repl.show(5) end, HERE,
        "bad argument #1 to 'show' (lancer.Image expected, got number)")
  check(function() repl.show(lancer.material{}) end, HERE,
        "(lancer.Image expected, got lancer.Material)")
  local img = lancer.image{width = 1, height = 1}
  do local x <close> = img end
  check(function() repl.show(img) end, HERE,
        "bad argument #1 to 'show' (lancer.Image already freed)")
end)
