-- docblocks.lua: reads the fenced code blocks of a Markdown file and
-- compares a program's output with the output a block shows; what
-- tests/lua/test_docs.lua needs, kept apart from its cases.
local M = {}

-- The blocks of `text` in order: {line, lang, words = {word = value or
-- true}, info, body = {lines}, file}. `line` is the fence's line number.
-- Fences open and close at the start of a line; an unclosed fence or an
-- indented one is an error, so no block escapes the test unseen. HTML
-- comments (<!-- ... -->, from a line that starts one) hold no blocks, as
-- Markdown shows none there.
function M.parse(text, file)
  local blocks, open, n, comment = {}, nil, 0, false
  for line in (text .. (text:sub(-1) == "\n" and "" or "\n")):gmatch("(.-)\n") do
    n = n + 1
    if comment then
      comment = not line:find("-->", 1, true)
    elseif not open and line:match("^%s*<!%-%-") then
      comment = not line:find("-->", 1, true)
    elseif open then
      if line:match("^```%s*$") then
        blocks[#blocks + 1] = open
        open = nil
      else
        open.body[#open.body + 1] = line
      end
    elseif line:match("^%s+```") then
      error(("%s:%d: an indented fence; fences start at the line's start"):format(file, n), 0)
    elseif line:match("^```") then
      local info = line:match("^```%s*(.-)%s*$")
      local lang, rest = info:match("^(%S*)%s*(.*)$")
      local words = {}
      for w in rest:gmatch("%S+") do
        local k, v = w:match("^([%w_]+)=(.+)$")
        if k then words[k] = v else words[w] = true end
      end
      open = {line = n, lang = lang, words = words, info = info, body = {}, file = file}
    end
  end
  if open then error(("%s:%d: the fence is never closed"):format(file, open.line), 0) end
  if comment then error(("%s: an HTML comment is never closed"):format(file), 0) end
  return blocks
end

-- A line as compared: no trailing spaces or carriage return, every time
-- ("0.041 s", "0.12s", "3.45 Mrays/s") one token; with `numbers`, every
-- number one token and runs of spaces one space.
function M.normalise(line, numbers)
  line = line:gsub("[\r%s]+$", "")
  line = line:gsub("%d+%.?%d* Mrays/s", "#T Mrays/s")
  line = line:gsub("%d+%.?%d* ?s%f[%W]", "#Ts")
  if numbers then
    line = line:gsub("[%-+]?%d+%.?%d*[eE][%-+]?%d+", "#")
    line = line:gsub("[%-+]?%d+%.?%d*", "#")
    line = line:gsub("%s+", " ")
  end
  return line
end

local function lines_of(s)
  local t = {}
  for l in (s:gsub("\n$", "") .. "\n"):gmatch("(.-)\n") do t[#t + 1] = l end
  while #t > 0 and t[#t]:match("^%s*$") do t[#t] = nil end
  return t
end
M.lines_of = lines_of

-- An expected line as a Lua pattern: literal, but "..." inside it matches
-- any text.
local function line_pattern(e)
  local parts = {}
  for piece in (e .. "..."):gmatch("(.-)%.%.%.") do
    parts[#parts + 1] = piece:gsub("[%^%$%(%)%%%.%[%]%*%+%-%?]", "%%%0")
  end
  return "^" .. table.concat(parts, ".-") .. "$"
end

-- Does `actual` (a string) read as `expected` (a list of lines)? A line
-- "..." matches any number of lines. Returns true, or false and a
-- description of the first difference.
function M.matches(expected, actual, numbers)
  local a = lines_of(actual)
  local e = {}
  for i, l in ipairs(expected) do e[i] = M.normalise(l, numbers) end
  while #e > 0 and e[#e] == "" do e[#e] = nil end
  for i, l in ipairs(a) do a[i] = M.normalise(l, numbers) end
  local pats = {}
  for i, l in ipairs(e) do pats[i] = l ~= "..." and line_pattern(l) end
  local best_i, best_j = 1, 1           -- the furthest point reached, for the message
  local memo = {}
  local function match(i, j)
    local key = i * 100003 + j
    if memo[key] ~= nil then return memo[key] end
    if i > best_i or (i == best_i and j > best_j) then best_i, best_j = i, j end
    local r
    if i > #e then
      r = j > #a
    elseif not pats[i] then
      r = false
      for k = j, #a + 1 do
        if match(i + 1, k) then r = true; break end
      end
    else
      r = j <= #a and a[j]:find(pats[i]) ~= nil and match(i + 1, j + 1)
    end
    memo[key] = r
    return r
  end
  if match(1, 1) then return true end
  return false, ("expected line %d: %s\n  got line %d: %s"):format(best_i,
    e[best_i] or "(end of output)", best_j, a[best_j] or "(end of output)")
end

return M
