-- embree.lua: lancer's ray queries against Embree 3's, in the same run, on the
-- same geometry and the same rays (build/bin/lc-raycast, tools/bench/raycast.c):
-- builds, primary + shadow rays and incoherent (cosine) rays on B2, B3 and
-- a 4 096-triangle closed mesh, medians of interleaved runs, the ratio
-- lancer / Embree, and where float and double disagree.
local M = {}

local fmt = string.format

-- Torus of 64 x 32 quads (4 096 triangles), closed, as an OBJ file.
function M.write_torus(path)
  local f = assert(io.open(path, "w"))
  f:write("# a closed torus, 64 x 32 quads: 4096 triangles (tools/bench/embree.lua)\n")
  local U, V, R, r = 64, 32, 1.0, 0.35
  for i = 0, U - 1 do
    local a = 2 * math.pi * i / U
    for j = 0, V - 1 do
      local b = 2 * math.pi * j / V
      local rho = R + r * math.cos(b)
      f:write(fmt("v %.17g %.17g %.17g\n", rho * math.cos(a), r * math.sin(b) + r,
                  rho * math.sin(a)))
    end
  end
  local function at(i, j) return (i % U) * V + (j % V) + 1 end
  for i = 0, U - 1 do
    for j = 0, V - 1 do
      f:write(fmt("f %d %d %d\nf %d %d %d\n", at(i, j), at(i + 1, j), at(i + 1, j + 1),
                  at(i, j), at(i + 1, j + 1), at(i, j + 1)))
    end
  end
  f:close()
end

-- The cases: lc-raycast's arguments, and which targets each carries.
M.CASES = {
  {key = "b2-1m", label = "B2 1M spheres", args = {"b2", "1000000"}, trace = 1.2,
   build = true},
  {key = "b3-1m", label = "B3 1M triangles", args = {"b3", "707"}, trace = 1.5,
   incoherent = 0.6, quick = true},
  {key = "b3-4m", label = "B3 4M triangles", args = {"b3", "1414"}, trace = 1.5,
   build = true},
  {key = "torus4k", label = "torus, 4k triangles", args = {"mesh", "torus4k.obj"},
   incoherent = 0.6, quick = true},
}

-- Parses lc-raycast's output: {what = {lancer, embree, ratio, rays, ...}},
-- agree = {primary = {...}, shadow = {...}, incoherent = {...}}.
local function parse(text)
  local out = {agree = {}}
  for line in text:gmatch("[^\n]+") do
    local what, rest = line:match("^raycast (%S+) (.*)$")
    if what == "agree" then
      local set, fields = rest:match("^(%S+) (.*)$")
      local t = {}
      for k, v in fields:gmatch("([%w_]+)=([-%d.e+]+)") do t[k] = tonumber(v) end
      out.agree[set] = t
    elseif what and what ~= "scene" then
      local t = {}
      for k, v in rest:gmatch("([%w_]+)=([-%d.e+]+)") do t[k] = tonumber(v) end
      out[what] = t
    end
  end
  return out
end

-- ctx: run, runstat, root, out, raycast (the binary), threads, quick, say.
function M.section(ctx)
  local lines = {"## Embree 3, same geometry, same rays", "",
    fmt("lancer's `lc_scene_intersect` / `lc_scene_occluded` against Embree's " ..
        "`rtcIntersect1` / `rtcOccluded1`, %d threads each, the same ray arrays " ..
        "(double for lancer, rounded to float for Embree), interleaved (lancer, " ..
        "Embree, lancer, ...); medians of %d runs. Times in seconds; ratio = lancer / " ..
        "Embree (< 1: lancer faster). Build = BVH build from the loaded geometry. " ..
        "Memory: each side's own bytes for the scene, lancer / Embree (lancer's " ..
        "counted allocations, Embree's memory monitor), once built and at the " ..
        "build's peak; the process peak holds both sides and the ray arrays.",
        ctx.threads, ctx.quick and 3 or 5), "",
    "| scene | build | primary | shadow | primary + shadow | incoherent | " ..
    "incoherent Mrays/s | memory MB, held (build peak) | process peak MB |",
    "|---|---|---|---|---|---|---|---|---|"}
  local checks, agree_lines = {}, {}
  M.write_torus(ctx.out .. "/torus4k.obj")
  for _, case in ipairs(M.CASES) do
    if case.quick or not ctx.quick then
      ctx.say("  %s", case.label)
      local argv = {ctx.raycast}
      for _, a in ipairs(case.args) do argv[#argv + 1] = a end
      argv[#argv + 1] = tostring(ctx.threads)
      argv[#argv + 1] = ctx.quick and "3" or "5"
      local log = fmt("%s/%s-raycast.log", ctx.out, case.key)
      local r = ctx.run.measure(ctx.runstat, argv, ctx.out, log)
      local p = r.status == 0 and parse(r.log)
      if not (p and p.build and p.primary) then
        ctx.say("  lc-raycast failed; the end of %s:\n%s", log, ctx.run.tail(r.log, 6))
        lines[#lines + 1] = fmt("| %s | failed | | | | | | | |", case.label)
      else
        local function cell(t) return fmt("%.3f / %.3f (%.2fx)", t.lancer, t.embree, t.ratio) end
        local inc = p.incoherent
        local m = p.memory or {}
        lines[#lines + 1] = fmt("| %s | %s | %s | %s | %s | %s | %.2f / %.2f (%.2fx) | " ..
          "%.1f (%.1f) / %.1f (%.1f) | %.0f |",
          case.label, cell(p.build), cell(p.primary), cell(p.shadow),
          cell(p["primary+shadow"]), cell(inc), inc.lancer_mrays, inc.embree_mrays,
          inc.lancer_mrays / inc.embree_mrays, m.lancer_mb or 0, m.lancer_build_mb or 0,
          m.embree_mb or 0, m.embree_build_mb or 0, r.rss_mb or 0)
        local a = p.agree
        agree_lines[#agree_lines + 1] = fmt("| %s | %d | %d | %d | %d | %.1e | %d of %d | %d | %d | %d |",
          case.label, a.primary.both, a.primary.only_lancer, a.primary.only_embree,
          a.primary.other_primitive, a.primary.max_rel_t, a.shadow.differ, a.shadow.rays,
          a.incoherent.only_lancer, a.incoherent.only_embree, a.incoherent.other_primitive)
        local ps = p["primary+shadow"]
        if case.trace then
          checks[#checks + 1] = {ps.ratio <= case.trace, fmt(
            "%s: primary + shadow trace %.3f s <= %.1f x Embree's %.3f s (%.2fx)",
            case.label, ps.lancer, case.trace, ps.embree, ps.ratio)}
        end
        if case.incoherent then
          local share = inc.lancer_mrays / inc.embree_mrays
          checks[#checks + 1] = {share >= case.incoherent, fmt(
            "%s: incoherent %.2f Mrays/s >= %.1f x Embree's %.2f (%.2fx)", case.label,
            inc.lancer_mrays, case.incoherent, inc.embree_mrays, share)}
        end
        if case.build then
          checks[#checks + 1] = {p.build.ratio <= 1, fmt(
            "%s: BVH build %.3f s no slower than Embree's %.3f s (%.2fx)", case.label,
            p.build.lancer, p.build.embree, p.build.ratio)}
        end
      end
    end
  end
  lines[#lines + 1] = ""
  lines[#lines + 1] = "Where they disagree (lancer in double, Embree in float; counted " ..
    "over the first run's rays). B2's ground is infinite in lancer and two triangles " ..
    "of side 2e5 in Embree: rays meeting it farther out (at the horizon) hit only in lancer."
  lines[#lines + 1] = ""
  lines[#lines + 1] = "| scene | primary: both hit | only lancer | only Embree | " ..
    "other primitive | max relative t difference | shadow rays that differ | " ..
    "incoherent: only lancer | only Embree | other primitive |"
  lines[#lines + 1] = "|---|---|---|---|---|---|---|---|---|---|"
  for _, l in ipairs(agree_lines) do lines[#lines + 1] = l end
  lines[#lines + 1] = ""
  lines[#lines + 1] = "Targets (same run):"
  lines[#lines + 1] = ""
  for _, c in ipairs(checks) do
    lines[#lines + 1] = fmt("- %s %s", c[1] and "PASS" or "FAIL", c[2])
  end
  return table.concat(lines, "\n") .. "\n"
end

return M
