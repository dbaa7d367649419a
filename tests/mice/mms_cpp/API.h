// The mms-cpp template's API, as it behaves (written for the tests).
#pragma once

#include <string>

class API {
public:
    static int mazeWidth();
    static int mazeHeight();
    static bool wallFront();
    static bool wallRight();
    static bool wallLeft();
    static void moveForward();
    static void turnRight();
    static void turnLeft();
    static void setWall(int x, int y, char direction);
    static void clearWall(int x, int y, char direction);
    static void setColor(int x, int y, char color);
    static void clearColor(int x, int y);
    static void clearAllColor();
    static void setText(int x, int y, const std::string& text);
    static void clearText(int x, int y);
    static void clearAllText();
    static bool wasReset();
    static void ackReset();
};
