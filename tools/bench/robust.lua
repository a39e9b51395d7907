-- robust.lua: what robustness costs. The same scenes traced by the normal
-- lancer and by `make NAIVE=1`'s (textbook sphere quadratic, a fixed 1e-4
-- spawn offset, Moller-Trumbore triangles), interleaved; the target is at
-- most 5 % more trace time for the robust code (docs/numerics.md T8).
local M = {}

M.TARGET = 1.05

M.CASES = {
  {label = "B2 100k spheres", script = "b2.lua", args = {"100000"}},
  {label = "B3 1M triangles", script = "b3.lua", args = {"707"}},
}

-- ctx: {run, runstat, root, out, robust, naive, runs, say}. Returns the
-- Markdown section.
function M.section(ctx)
  local run, rows = ctx.run, {}
  local lines = {"## What robustness costs\n\n",
    "Trace seconds (median of ", ctx.runs, " interleaved runs) of the robust build and of\n",
    "`make NAIVE=1` (naive sphere quadratic, fixed 1e-4 spawn offset, Moller-Trumbore);\n",
    "the overhead is the median of the runs' pairwise ratios.\n\n",
    "| scene | robust trace (s) | naive trace (s) | overhead | target (<= 5 %) |\n",
    "| --- | --- | --- | --- | --- |\n"}
  for _, case in ipairs(M.CASES) do
    local times = {robust = {}, naive = {}}
    for i = 1, ctx.runs do
      for _, which in ipairs{"robust", "naive"} do
        local argv = {ctx[which], "scenes/bench/" .. case.script}
        for _, a in ipairs(case.args) do argv[#argv + 1] = a end
        local log = ("%s/robust-%s.log"):format(ctx.out, which)
        local r = run.measure(ctx.runstat, argv, ctx.root, log)
        if r.bench.trace then
          times[which][#times[which] + 1] = r.bench.trace
          ctx.say("  %-6s %s run %d: trace %.3f s", which, case.label, i, r.bench.trace)
        else
          ctx.say("  %s failed:\n%s", which, run.tail(r.log, 6))
        end
      end
    end
    local a, b = run.median(times.robust), run.median(times.naive)
    -- The median of each run's ratio to its neighbour's: a noisy spell
    -- slows both halves of a pair, so it cancels (the machine drifts).
    local ratios = {}
    for i = 1, math.min(#times.robust, #times.naive) do
      ratios[i] = times.robust[i] / times.naive[i]
    end
    local over = run.median(ratios)
    lines[#lines + 1] = ("| %s | %s | %s | %s | %s |\n"):format(case.label,
      a and ("%.3f"):format(a) or "-", b and ("%.3f"):format(b) or "-",
      over and ("%+.1f %%"):format(100 * (over - 1)) or "-",
      over and (over <= M.TARGET and "PASS" or "MISS") or "-")
  end
  return table.concat(lines) .. "\n"
end

return M
