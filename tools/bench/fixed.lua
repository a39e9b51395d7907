-- fixed.lua: the fixed cost of a run (start-up, Lua, the BVH, the PNG save
-- with its fsync, the exit) beside the trace of a 1280x720 frame, B1 at
-- 1 spp: the cheapest frame of the bench, so the largest share.
--
-- Each part is timed as a whole process under lc-runstat, interleaved:
--   start-up     `lancer -e ''`: exec, linking, the Lua state, the module
--   B1           scenes/bench/b1.lua, no save: its own line gives Lua, build
--                and trace; the rest of its wall is start-up, set-up, exit
--   save         tools/bench/fixed_saves.lua saving B1's frame SAVES times
--                against 0 times: the wall per save; its CPU time is the
--                encoding, the rest the write, fsync and rename
local M = {}

M.SAVES = 10
M.TARGET = 0.25        -- the fixed cost at most this share of B1's 1-spp trace

-- ctx: {run, runstat, root, out, lancer, runs, say}. Returns the section.
function M.section(ctx)
  local run, out = ctx.run, ctx.out
  local frame = out .. "/fixed-b1.png"
  local t = {startup = {}, wall = {}, lua = {}, build = {}, trace = {}, rest = {},
             around = {}, saves = {}, cpu = {}}
  local function measure(name, argv)
    local r = run.measure(ctx.runstat, argv, ctx.root, ("%s/fixed-%s.log"):format(out, name))
    if not r.wall or r.status ~= 0 then
      ctx.say("  %s failed:\n%s", name, run.tail(r.log, 6))
      return nil
    end
    return r
  end
  -- The frame the saves write, rendered once first (not counted).
  measure("frame", {ctx.lancer, "scenes/bench/b1.lua", "1", frame})
  for i = 1, ctx.runs do
    local r = measure("startup", {ctx.lancer, "-e", ""})
    if r then t.startup[#t.startup + 1] = r.wall end
    local up = r and r.wall
    r = measure("b1", {ctx.lancer, "scenes/bench/b1.lua", "1"})
    if r and r.bench.trace and up then
      local b = r.bench
      t.wall[#t.wall + 1] = r.wall
      t.lua[#t.lua + 1] = b.lua
      t.build[#t.build + 1] = b.build
      t.trace[#t.trace + 1] = b.trace
      -- per run, then the median: parts of one run stay consistent
      t.around[#t.around + 1] = r.wall - b.trace
      t.rest[#t.rest + 1] = r.wall - up - b.lua - b.build - b.trace
    end
    local r0 = measure("save0", {ctx.lancer, "tools/bench/fixed_saves.lua", frame, "0",
                                 out .. "/fixed-save.png"})
    local rn = measure("saves", {ctx.lancer, "tools/bench/fixed_saves.lua", frame,
                                 tostring(M.SAVES), out .. "/fixed-save.png"})
    if r0 and rn and rn.bench.cpu then
      t.saves[#t.saves + 1] = (rn.wall - r0.wall) / M.SAVES
      t.cpu[#t.cpu + 1] = rn.bench.cpu / M.SAVES
    end
    ctx.say("  run %d: start-up %.4f s, B1 wall %.3f s, a save %.4f s", i,
            t.startup[#t.startup] or -1, t.wall[#t.wall] or -1, t.saves[#t.saves] or -1)
  end
  local m = {}
  for k, list in pairs(t) do m[k] = run.median(list) end
  local lines = {"## The fixed cost of a run\n\n",
    ("B1 at 1280x720, 1 spp, and the parts of a run around its trace; medians of %d\n"
     .. "interleaved runs, each a whole process (lc-runstat). A save is the wall of saving\n"
     .. "B1's frame %d times less that of loading it alone, over %d; its CPU time is the\n"
     .. "PNG encoding, the rest the write, fsync and rename.\n\n"):format(ctx.runs, M.SAVES,
                                                                        M.SAVES)}
  if not (m.startup and m.wall and m.trace and m.saves and m.cpu) then
    return table.concat(lines) .. "(not measured: a part failed, see out/bench/fixed-*.log)\n"
  end
  local rest = m.rest
  local fixed = m.around + m.saves
  local function row(part, s)
    return ("| %s | %.4f | %.1f %% |\n"):format(part, s, 100 * s / m.trace)
  end
  lines[#lines + 1] = "| part | seconds | of the trace |\n| --- | --- | --- |\n"
  lines[#lines + 1] = row("start-up: exec, Lua, the lancer module (`lancer -e ''`)", m.startup)
  lines[#lines + 1] = row("the script's Lua (building the scene)", m.lua)
  lines[#lines + 1] = row("BVH build", m.build)
  lines[#lines + 1] = row("trace, 1280x720", m.trace)
  lines[#lines + 1] = row("the rest of B1's wall: set-up, image, exit", rest)
  lines[#lines + 1] = row("PNG save: encoding (CPU)", m.cpu)
  lines[#lines + 1] = row("PNG save: write, fsync, rename", m.saves - m.cpu)
  lines[#lines + 1] = row("**fixed cost: all but the trace**", fixed)
  lines[#lines + 1] = ("\n- %s  fixed cost %.4f s <= %.2f x the trace %.3f s = %.3f s\n"):format(
    fixed <= M.TARGET * m.trace and "PASS" or "MISS", fixed, M.TARGET, m.trace,
    M.TARGET * m.trace)
  return table.concat(lines) .. "\n"
end

return M
