-- test_explain.lua: explain's ray trees at any size: long texts, deep
-- chains of mirror bounces, and trees a script has changed, all print.
local T = require "harness"
local lancer = require "lancer"

-- A plane under n point lights: the camera ray and n shadow rays.
local function many_lights(n)
  local s = lancer.scene{camera = lancer.camera{from = {0, 1, -4}, at = {0, 1, 0}}}
  s:add(lancer.plane{point = {0, 0, 0}, normal = {0, 1, 0}})
  for i = 1, n do s:add(lancer.point_light{position = {i, 4, -3}, intensity = 5}) end
  return s
end

-- Two facing mirrors, the camera between them looking at one: every
-- bounce goes back along the axis, so a sample bounces `depth` times.
local function mirrors(depth)
  local m = lancer.material{color = {1, 1, 1}, ka = 0, kd = 0, ks = 0, kr = 1}
  local s = lancer.scene{camera = lancer.camera{from = {0, 0, -0.5}, at = {0, 0, 1}},
                         max_depth = depth}
  s:add(lancer.plane{point = {0, 0, 1}, normal = {0, 0, -1}, material = m},
        lancer.plane{point = {0, 0, -1}, normal = {0, 0, 1}, material = m},
        lancer.point_light{position = {0, 0.5, 0}, intensity = 1})
  return s
end

local function lines(s)
  local out = {}
  for l in s:gmatch("[^\n]+") do out[#out + 1] = l end
  return out
end

T.test("a tree of 40 shadow rays prints whole (the text passes luaL_Buffer's 1 KB)",
       function()
  local tree = many_lights(40):explain{x = 32, y = 40, width = 64, height = 48}
  T.eq(#tree.rays, 40, "shadow rays")
  local ok, text = pcall(tostring, tree)
  assert(ok, text)
  assert(#text > 2048, "a short text: " .. #text)
  local l = lines(text)
  T.eq(#l, 41, "lines")
  T.has(l[1], "camera hits plane 1")
  T.has(l[41], "  shadow to point light 40: visible")
end)

T.test("1000 mirror bounces: the whole tree in tables, printed to 100 levels, fast",
       function()
  local s = mirrors(1000)
  local t0 = os.clock()
  local tree = s:explain{x = 1, y = 1, width = 1, height = 1, cutoff = 0,
                         max_depth = 1000}
  local t1 = os.clock()
  local text = tostring(tree)
  local t2 = os.clock()
  -- The chain, every level a shadow ray and a reflection that goes on.
  local node, bounces = tree, 0
  while true do
    local refl
    for _, r in ipairs(node.rays) do
      if r.kind == "reflection" then refl = r end
    end
    if not refl then break end
    bounces, node = bounces + 1, refl
  end
  T.eq(bounces, 1000, "reflection rays in the chain")
  local l = lines(text)
  -- Levels 0..99 print, the camera ray and 99 reflections (no shadow
  -- rays: mirrors have no diffuse term); the other 901 are one note.
  T.eq(#l, 101, "lines printed")
  T.has(l[100], string.rep("  ", 99) .. "reflection hits plane")
  T.has(l[101], string.rep("  ", 100) .. "... 901 more rays below")
  T.has(l[#l], "the print stops at 100 levels")
  assert(t1 - t0 < 0.5, ("explain took %.3f s"):format(t1 - t0))
  assert(t2 - t1 < 0.5, ("printing took %.3f s"):format(t2 - t1))
  -- A deeper node prints from where it is: the rest of the chain.
  local sub = tostring(node)
  T.has(sub, "reflection hits plane")
end)

T.test("a printed tree reads its tables raw and survives a script's edits", function()
  local tree = many_lights(2):explain{x = 32, y = 40, width = 64, height = 48}
  -- Metamethods on a node are not called: nothing runs while printing.
  setmetatable(tree.rays[1], {__index = function() error("called") end,
                              __tostring = getmetatable(tree).__tostring})
  tree.rays[2].kind = {}                 -- not a string
  tree.rays[2].contribution = "x"        -- not a colour
  tree.rays[3] = tree                    -- a cycle
  local text = tostring(tree)
  local l = lines(text)
  T.has(l[2], "  shadow to point light 1")
  T.has(l[3], "  ? to point light 2")
  T.has(l[4], "  (a ray printed above)")
  T.eq(#l, 4, "lines")
end)
