// SPDX-License-Identifier: Apache-2.0
// Refusing a run whose outputs would overwrite its input or each other: a user who types
// an output path that is the input, or the same as another output, loses data without a word otherwise.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace lasmesh {

// True when `a` and `b` name one file: the same device and inode when both exist (links and
// different spellings included), else the same canonical folder and file name. "-" stands for
// standard input: the file redirected into it, if it is a regular file.
bool same_file(const std::string& a, const std::string& b);

// Each entry is (role, path), e.g. ("-o", "out.ply") or ("the input", "in.las"); "-" (standard
// input) is the file redirected into it, when one is. Throws Error (usage) naming both roles and paths when two entries
// are the same file. Call it before reading anything.
void check_distinct_files(const std::vector<std::pair<std::string, std::string>>& paths);

// The same for many inputs (thousands) and a few outputs: no input given twice (its points would
// count twice), no output that is an input, no two outputs the same file.
void check_distinct_inputs(const std::vector<std::string>& inputs,
                           const std::vector<std::pair<std::string, std::string>>& outputs);

} // namespace lasmesh
