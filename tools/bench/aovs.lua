-- aovs.lua: what the AOVs cost: the Cornell box (scenes/cornell.lua)
-- rendered with every AOV or none, Whitted's shading or paths.
-- Usage: lancer tools/bench/aovs.lua none|all [indirect] [samples]
-- Prints one line to stderr: bench aovs=<none|all> indirect=<n> trace=<s>
local lancer = require "lancer"
local which = arg and arg[1] or "none"
local indirect = tonumber(arg and arg[2]) or 0
local samples = tonumber(arg and arg[3]) or 4
local scene = assert(loadfile("scenes/cornell.lua"))("--scene")
local all = {'depth', 'normal', 'albedo', 'position', 'object', 'material', 'direct',
             'reflection', 'refraction', 'indirect', 'emission'}
local _, st = scene:render{width = 320, height = 320, samples = samples,
                           indirect = indirect, aovs = which == "all" and all or nil}
io.stderr:write(("bench aovs=%s indirect=%d trace=%.4f\n"):format(which, indirect,
                                                                  st.trace_seconds))
