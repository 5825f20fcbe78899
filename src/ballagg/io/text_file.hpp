#pragma once
// Reading a whole input file, with the one-line errors of bad input.
#include <string>

namespace ballagg {

// The contents of `path`. Throws InputError "PATH: cannot read the WHAT: reason" when it is
// missing, unreadable or a directory.
std::string read_text_file(const std::string& path, const std::string& what);

}  // namespace ballagg
