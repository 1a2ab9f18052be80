// KeyScript: the factory window's input written as text (--keys) and replayed one frame after another, so that
// a run without a person (a test, a demo under xvfb-run) presses the same keys and drags as one with.
#pragma once
#include <string>
#include <vector>

namespace factory {

// The window's keys, whether pressed on the keyboard or replayed.
enum class Key { Forward, Back, Left, Right, FlyWalk, LodMode, Occlusion, Screenshot, Overlay, Quit };

struct ScriptFrame {
    std::vector<Key> pressed;  // keys other than movement pressed (down) on this frame
    bool forward = false, back = false, left = false, right = false;  // movement keys held this frame
    double dragX = 0.0, dragY = 0.0;                                  // a left-button drag, pixels
    bool click = false;                                               // a left click at (clickX, clickY)
    double clickX = 0.0, clickY = 0.0;                                // framebuffer pixels, y down
};

// Tokens separated by spaces, each one frame or more:
//   W A S D          a movement key held for one frame; W*30 for 30 frames
//   F M O P F12 H Esc  pressed on one frame (F*10: pressed, then 9 frames of nothing)
//   drag:DX,DY       a left-button drag of DX, DY pixels (turns the view)
//   click:X,Y        a left click at pixel (X, Y), y down (picks: the feature there is shown)
//   wait*N           N frames of nothing (wait: one)
// Letters in either case. Throws std::invalid_argument naming the token that is none of these.
std::vector<ScriptFrame> parseKeyScript(const std::string& text);

}  // namespace factory
