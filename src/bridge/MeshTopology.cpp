#include "MeshTopology.h"

#include <algorithm>
#include <utility>

namespace masse::bridge
{
std::optional<MeshEdge> findOpenEdge(const std::vector<std::vector<int>>& faces)
{
    std::vector<std::pair<int, int>> edges;
    for (const std::vector<int>& face : faces)
    {
        for (std::size_t k = 0; k < face.size(); ++k)
        {
            const int a = face[k];
            const int b = face[(k + 1) % face.size()];
            edges.emplace_back(std::min(a, b), std::max(a, b));
        }
    }
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size();)
    {
        std::size_t j = i;
        while (j < edges.size() && edges[j] == edges[i])
        {
            ++j;
        }
        if (j - i != 2)
        {
            return MeshEdge{edges[i].first, edges[i].second, int(j - i)};
        }
        i = j;
    }
    return std::nullopt;
}
} // namespace masse::bridge
