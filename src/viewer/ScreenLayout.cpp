#include "ScreenLayout.h"

#include <algorithm>

namespace masse::viewer
{
ScreenLayout screenLayout(int windowWidth, int windowHeight, bool showUi)
{
    ScreenLayout layout;
    const int width = std::max(1, windowWidth);
    const int height = std::max(1, windowHeight);
    layout.window = {0, 0, width, height};
    const int column = showUi ? std::min(columnWidth, int(maxColumnShare * width)) : 0;
    layout.scene = {0, 0, std::max(1, width - column), height};
    layout.column = {layout.scene.right(), 0, width - layout.scene.width, height};
    return layout;
}
} // namespace masse::viewer
