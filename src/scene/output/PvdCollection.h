#pragma once
/// A ParaView data collection (.pvd): which file holds which part of the scene at which simulated time. ParaView
/// opens it as one time series (its time is the simulated time in seconds, not a frame number) with one block per
/// part: the sheet, then each obstacle.

#include "core/Types.h"

#include <string>
#include <vector>

namespace masse::scene
{
class PvdCollection
{
public:
    /// One dataset: `file` relative to the .pvd, `part` its block (the same name keeps the same part).
    void add(Real time, int part, const std::string& name, const std::string& file);
    std::size_t size() const { return m_entries.size(); }
    /// The collection as XML.
    std::string text() const;

private:
    struct Entry
    {
        Real time;
        int part;
        std::string name;
        std::string file;
    };
    std::vector<Entry> m_entries;
};
} // namespace masse::scene
