// notes.h — warnings a loader gives once per kind: the first place and how many times.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace wp {

class NoteLog {
public:
    // Records one occurrence of the note `key`; its text and place are the first one's.
    void add(const std::string& key, std::string where, std::string text) {
        auto [it, fresh] = index_.try_emplace(key, notes_.size());
        if (fresh) notes_.push_back({std::move(text), std::move(where), 0});
        ++notes_[it->second].count;
    }
    // One line per note, in the order first met: "WHERE: TEXT" or
    // "WHERE: TEXT (N times; the first here)".
    void append_to(std::vector<std::string>& warnings) const;

private:
    struct Note {
        std::string text, where;
        int count = 0;
    };
    std::vector<Note> notes_;
    std::map<std::string, std::size_t> index_;
};

}  // namespace wp
