-- test_citations.lua: every Markdown file the sources, tests, tools, scenes,
-- examples and docs cite exists in the repository, so a comment such as
-- "docs/numerics.md 1.12" always leads somewhere a reader can open.
--
-- What counts as a citation: a name ending in .md in the comments of C files
-- (their code names no document; a member called md is no citation) and
-- anywhere in every other text file. A name resolves when the file exists
-- beside the citing file, from the repository's top, or (a bare name such as
-- manual.md) in docs/. Not citations: names under out/ or build/, which
-- `make` writes (out/bench/results.md), and the tails of paths joined in
-- code (OUT .. "/results.md"). Run from the repository's top, as all.lua is.
local T = require "harness"

local ROOTS = {"src", "lua", "tests", "tools", "scenes", "examples", "docs"}
local TOP_FILES = {"README.md", "Makefile"}

-- The text files to read: the folders' files (tests/out/ holds test output)
-- and the top-level ones, binary files (a NUL byte) left out.
local function text_files()
  local files = {}
  local p = assert(io.popen("find " .. table.concat(ROOTS, " ") ..
                            " -type f ! -path 'tests/out/*' | sort"))
  for path in p:lines() do files[#files + 1] = path end
  p:close()
  for _, f in ipairs(TOP_FILES) do files[#files + 1] = f end
  local texts = {}
  for _, path in ipairs(files) do
    local text = T.slurp(path)
    if text and not text:find("\0", 1, true) then
      texts[#texts + 1] = {path = path, text = text}
    end
  end
  return texts
end

-- The comments of a C file, each comment's text in place of the code
-- around it, line breaks kept so that line numbers still count.
local function c_comments(text)
  local out, i = {}, 1
  while true do
    local b, l = text:find("/*", i, true), text:find("//", i, true)
    local s = (b and l) and math.min(b, l) or b or l
    if not s then break end
    out[#out + 1] = (text:sub(i, s - 1):gsub("[^\n]", ""))
    local e = s == b and (text:find("*/", s + 2, true) or #text) + 1 or
              (text:find("\n", s, true) or #text + 1) - 1
    out[#out + 1] = text:sub(s, e)
    i = e + 1
  end
  out[#out + 1] = (text:sub(i):gsub("[^\n]", ""))
  return table.concat(out)
end

local function exists(path)
  local f = io.open(path, "rb")
  if not f then return false end
  f:close()
  return true
end

-- Does `name`, cited in the file at `from`, lead to a file?
local function resolves(name, from)
  local dir = from:match("^(.*)/") or "."
  if exists(dir .. "/" .. name) or exists(name) then return true end
  return not name:find("/", 1, true) and exists("docs/" .. name)
end

-- Every {name, line} the text cites.
local function citations(text)
  local found, line, pos = {}, 1, 1
  for s, name in text:gmatch("()([%w_%./%-]*[%w_]%.md)%f[^%w_]") do
    line = line + select(2, text:sub(pos, s - 1):gsub("\n", ""))
    pos = s
    name = name:gsub("^%./", "")
    if not (name:match("^/") or name:match("^out/") or name:match("^build/")) then
      found[#found + 1] = {name = name, line = line}
    end
  end
  return found
end

T.test("citations: every cited .md file exists in the repository", function()
  local missing, seen = {}, 0
  for _, f in ipairs(text_files()) do
    local text = f.path:match("%.[ch]$") and c_comments(f.text) or f.text
    for _, c in ipairs(citations(text)) do
      seen = seen + 1
      if not resolves(c.name, f.path) then
        missing[#missing + 1] = ("%s:%d: %s"):format(f.path, c.line, c.name)
      end
    end
  end
  assert(seen > 0, "no citation found: the scan reads nothing")
  assert(#missing == 0, ("%d citations of files that do not exist:\n  %s"):format(
    #missing, table.concat(missing, "\n  ")))
end)

-- The documents cited before docs/ held them went by bare titles too
-- ("NUMERICS H33"); a title alone names no file a reader can open.
T.test("citations: no document is cited by a bare title", function()
  local titles = {"NUMERICS", "ECOSYSTEM", "BENCH"}
  local found = {}
  for _, f in ipairs(text_files()) do
    if f.path ~= "tests/lua/test_citations.lua" then
      local text = f.path:match("%.[ch]$") and c_comments(f.text) or f.text
      local n = 0
      for line in (text .. "\n"):gmatch("(.-)\n") do
        n = n + 1
        for _, title in ipairs(titles) do
          if line:find("%f[%w_]" .. title .. "%f[^%w_]") then
            found[#found + 1] = ("%s:%d: %s"):format(f.path, n, title)
          end
        end
      end
    end
  end
  assert(#found == 0, ("%d citations by a bare title:\n  %s"):format(
    #found, table.concat(found, "\n  ")))
end)
