-- scene:explain, likewise: lc_scene_explain gets a NULL scene.
local lancer = require "lancer"
lancer.set_host_hook(nil)                 -- as under lua5.4: no host in between
local s = lancer.scene{camera = lancer.camera{from = {0, 0, -4}, at = {0, 0, 0}}}
local opts = setmetatable({}, {__index = function(_, k)
  getmetatable(s).__close(s)
  return ({x = 1, y = 1, width = 4, height = 4, threads = 1})[k]
end})
s:explain(opts)
