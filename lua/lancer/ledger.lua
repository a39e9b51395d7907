-- lancer.ledger: a render's statistics as a readable table, what
-- `lancer --stats` prints after each render (lancer.ledger(stats) in a script).
local M = {}

local KINDS = {"camera", "shadow", "reflection", "refraction", "glossy", "light", "cut"}
local EFFECTS = {"shadow", "emitter", "area", "specular", "reflect", "refract", "filter",
                 "glossy", "ambient", "lens"}

function M.format(st, label)
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
  add("  tests     %d primitive, %d BVH node (%.1f and %.1f per ray)", st.prim_tests,
      st.node_tests, total > 0 and st.prim_tests / total or 0,
      total > 0 and st.node_tests / total or 0)
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
