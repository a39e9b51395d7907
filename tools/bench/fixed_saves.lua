-- fixed_saves.lua: loads a PNG (the B1 frame fixed.lua rendered) and saves it
-- N times as a script would (img:save, 8-bit sRGB, written beside its target,
-- fsynced, renamed): the save's share of a run, for tools/bench/fixed.lua.
-- Usage: lancer tools/bench/fixed_saves.lua in.png N out.png
-- Prints: bench saves n=N cpu=<s> (the CPU time of the N saves)
local lancer = require "lancer"
local img = lancer.load_png(arg[1], {encoding = "linear"})
local n = math.tointeger(tonumber(arg[2])) or error("N: an integer expected")
local t0 = os.clock()
for _ = 1, n do img:save(arg[3]) end
io.stderr:write(("bench saves n=%d cpu=%.5f\n"):format(n, os.clock() - t0))
