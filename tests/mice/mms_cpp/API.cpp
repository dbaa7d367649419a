// Commands on std::cout (std::endl flushes), answers read word by word from std::cin, as the template does.
#include "API.h"

#include <cstdlib>
#include <iostream>

static std::string ask(const std::string& line) {
    std::cout << line << std::endl;
    std::string answer;
    std::cin >> answer;
    return answer;
}

int API::mazeWidth() { return std::atoi(ask("mazeWidth").c_str()); }
int API::mazeHeight() { return std::atoi(ask("mazeHeight").c_str()); }
bool API::wallFront() { return ask("wallFront") == "true"; }
bool API::wallRight() { return ask("wallRight") == "true"; }
bool API::wallLeft() { return ask("wallLeft") == "true"; }
void API::moveForward() {
    std::string answer = ask("moveForward");
    if (answer != "ack") {
        std::cerr << answer << std::endl;
        std::exit(1);
    }
}
void API::turnRight() { ask("turnRight"); }
void API::turnLeft() { ask("turnLeft"); }
void API::setWall(int x, int y, char d) { std::cout << "setWall " << x << " " << y << " " << d << std::endl; }
void API::clearWall(int x, int y, char d) { std::cout << "clearWall " << x << " " << y << " " << d << std::endl; }
void API::setColor(int x, int y, char c) { std::cout << "setColor " << x << " " << y << " " << c << std::endl; }
void API::clearColor(int x, int y) { std::cout << "clearColor " << x << " " << y << std::endl; }
void API::clearAllColor() { std::cout << "clearAllColor" << std::endl; }
void API::setText(int x, int y, const std::string& t) { std::cout << "setText " << x << " " << y << " " << t << std::endl; }
void API::clearText(int x, int y) { std::cout << "clearText " << x << " " << y << std::endl; }
void API::clearAllText() { std::cout << "clearAllText" << std::endl; }
bool API::wasReset() { return ask("wasReset") == "true"; }
void API::ackReset() { ask("ackReset"); }
