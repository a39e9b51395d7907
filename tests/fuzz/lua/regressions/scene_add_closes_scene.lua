-- scene:add checks its arguments, then adds them; a list whose length,
-- read between the two passes, closes the scene leaves add with a freed
-- (NULL) scene: lc_scene_add_light(NULL, ...).
local lancer = require "lancer"
local s = lancer.scene{}
local light = lancer.point_light{position = {0, 1, 0}}
local list = setmetatable({}, {__len = function() getmetatable(s).__close(s); return 0 end})
s:add(light, list)
