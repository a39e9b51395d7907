-- scene:add, the scene closed by the next argument's __len before the
-- sphere is added: lc_scene_add_shape(NULL, ...) reads the material count
-- of a NULL scene (check_material).
local lancer = require "lancer"
local s = lancer.scene{}
local ball = lancer.sphere{center = {0, 0, 0}, radius = 1}
s:add(lancer.sphere{center = {0, 2, 0}, radius = 1})   -- the default material is in
local list = setmetatable({}, {__len = function() getmetatable(s).__close(s); return 0 end})
s:add(ball, list)
