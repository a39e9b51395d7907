-- scene:add, likewise for a shape with its own material: the binding's
-- material_index calls lc_scene_add_material(NULL, ...).
local lancer = require "lancer"
local s = lancer.scene{}
local ball = lancer.sphere{center = {0, 0, 0}, radius = 1, material = lancer.material{kr = 0.5}}
local list = setmetatable({}, {__len = function() getmetatable(s).__close(s); return 0 end})
s:add(ball, list)
