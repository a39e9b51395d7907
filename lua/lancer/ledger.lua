-- lancer.ledger: a render's statistics as a readable table, what
-- `lancer --stats` prints after each render (lancer.ledger(stats) in a script).
local M = {}

local KINDS = {"camera", "shadow", "reflection", "refraction", "glossy", "light", "indirect",
               "ao", "cut"}
local EFFECTS = {"shadow", "spot", "sun", "emitter", "area", "specular", "reflect",
                 "refract", "filter", "glossy", "ambient", "lens", "sky", "indirect", "ao"}

-- The fields format reads: integers, numbers, tables (nil allowed for the
-- optional ones, which older statistics lack).
local INTEGERS = {"threads", "prim_tests", "node_tests", "primitives", "bvh_nodes",
                  "degenerate", "self_hits"}
local NUMBERS = {"seconds", "compile_seconds", "trace_seconds"}
local OPTIONAL = {{"lua_seconds", "number"}, {"samples", "integer"},
                  {"converged", "integer"}, {"why", "table"}, {"csg_tests", "integer"},
                  {"aovs", "table"}}

local function got(v)
  if v == nil then return "no value" end
  if math.type(v) == "float" then return tostring(v) end
  return type(v)
end

-- What is wrong with st[k] (`name` in the message), wanted a `want`; nil
-- when nothing is.
local function problem(v, name, want)
  local ok = want == "table" and type(v) == "table" or
             want == "number" and type(v) == "number" or
             want == "integer" and math.tointeger(v) ~= nil
  if not ok then
    return ("field '%s': %s expected, got %s"):format(name, want, got(v))
  end
end

-- Raises at format's caller unless st is the statistics table of a render.
local function check(st, label)
  local function bad(why) error("bad argument #1 to 'ledger' (" .. why .. ")", 4) end
  if type(st) ~= "table" then
    bad("statistics table of a render expected, got " .. got(st))
  end
  if label ~= nil and type(label) ~= "string" then
    error(("bad argument #2 to 'ledger' (string expected, got %s)"):format(
      type(label)), 3)
  end
  for _, k in ipairs(INTEGERS) do
    local why = problem(st[k], k, "integer")
    if why then bad(why) end
  end
  for _, k in ipairs(NUMBERS) do
    local why = problem(st[k], k, "number")
    if why then bad(why) end
  end
  for _, f in ipairs(OPTIONAL) do
    local why = st[f[1]] ~= nil and problem(st[f[1]], f[1], f[2])
    if why then bad(why) end
  end
  for _, k in ipairs{"rays", "effects"} do
    local why = problem(st[k], k, "table")
    if why then bad(why) end
  end
  for _, k in ipairs(KINDS) do
    local why = st.rays[k] ~= nil and problem(st.rays[k], "rays." .. k, "integer")
    if why then bad(why) end
  end
end

-- lancer.ledger(stats [, label]): the statistics of a render as lines of text.
function M.format(st, label)
  check(st, label)
  local out = {}
  local function add(fmt, ...) out[#out + 1] = fmt:format(...) end
  local total = 0
  for _, k in ipairs(KINDS) do
    if k ~= "cut" then total = total + (st.rays[k] or 0) end
  end
  add("%s: %.3f s on %d thread%s (Lua scene %.3f s, compile %.3f s, trace %.3f s)",
      label or "render", st.seconds, st.threads, st.threads == 1 and "" or "s",
      st.lua_seconds or 0, st.compile_seconds, st.trace_seconds)
  local rays = {}
  for _, k in ipairs(KINDS) do rays[#rays + 1] = ("%s %d"):format(k, st.rays[k] or 0) end
  add("  rays      %s; %d traced, %.2f Mrays/s", table.concat(rays, ", "), total,
      st.trace_seconds > 0 and total / st.trace_seconds / 1e6 or 0)
  if st.samples then
    add("  samples   %d camera samples%s", st.samples,
        (st.converged or 0) > 0 and (", %d pixels converged early"):format(st.converged) or "")
  end
  if st.aovs and #st.aovs > 0 then     -- a render without AOVs shows nothing here
    add("  aovs      %s", table.concat(st.aovs, ", "))
  end
  add("  tests     %d primitive, %d BVH node (%.1f and %.1f per ray)", st.prim_tests,
      st.node_tests, total > 0 and st.prim_tests / total or 0,
      total > 0 and st.node_tests / total or 0)
  if (st.csg_tests or 0) > 0 then      -- a scene without CSG pays nothing, shows nothing
    add("  csg       %d leaf tests in the interval sweeps (%.1f per ray)", st.csg_tests,
        total > 0 and st.csg_tests / total or 0)
  end
  add("  scene     %d primitives, %d BVH nodes, %d degenerate triangles skipped, %d self-hits",
      st.primitives, st.bvh_nodes, st.degenerate, st.self_hits)
  for i, e in ipairs(EFFECTS) do
    add("  %-9s %-3s %s", i == 1 and "effects" or "", st.effects[e] and "on" or "off",
        ("%-9s %s"):format(e, st.why and st.why[e] or ""))
  end
  return table.concat(out, "\n")
end

-- Called for each render by the lancer command's host hook under --stats.
M.count = 0
function M.report(st)
  M.count = M.count + 1
  io.stderr:write(M.format(st, "render " .. M.count), "\n")
end

return M
