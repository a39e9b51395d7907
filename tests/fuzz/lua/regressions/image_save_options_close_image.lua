-- img:save checks the image, then reads its options (encoding) through
-- __index; an option that closes the image leaves save writing freed
-- pixels (heap-use-after-free in write_png).
local lancer = require "lancer"
lancer.set_host_hook(nil)                 -- as under lua5.4: no host in between
local img = lancer.image{width = 2, height = 2}
local opts = setmetatable({}, {__index = function() getmetatable(img).__close(img) end})
img:save("closed.png", opts)
