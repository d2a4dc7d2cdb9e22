#pragma once
// A detector's planes, its per-chunk lists joined in chunk order (mass order), for tests that read them as one list.

#include "core/contact/Contact.h"

#include <vector>

namespace masse::test
{
inline std::vector<ContactPlane> joinedPlanes(const ContactPlaneLists& lists)
{
    std::vector<ContactPlane> planes;
    for (std::size_t list = 0; list < lists.size(); ++list)
    {
        planes.insert(planes.end(), lists[list].begin(), lists[list].end());
    }
    return planes;
}
} // namespace masse::test
