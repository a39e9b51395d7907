-- scene:render reads its options through __index after checking the scene;
-- an option that closes the scene leaves lc_scene_render a NULL scene.
local lancer = require "lancer"
lancer.set_host_hook(nil)                 -- as under lua5.4: no host in between
local s = lancer.scene{camera = lancer.camera{from = {0, 0, -4}, at = {0, 0, 0}}}
local opts = setmetatable({}, {__index = function(_, k)
  getmetatable(s).__close(s)
  return ({width = 4, height = 4, threads = 1})[k]
end})
s:render(opts)
