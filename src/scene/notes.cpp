#include "scene/notes.h"

#include <fmt/format.h>

namespace wp {

void NoteLog::append_to(std::vector<std::string>& warnings) const {
    for (const Note& nt : notes_)
        warnings.push_back(nt.count == 1 ? fmt::format("{}: {}", nt.where, nt.text)
                                         : fmt::format("{}: {} ({} times; the first here)",
                                                       nt.where, nt.text, nt.count));
}

}  // namespace wp
