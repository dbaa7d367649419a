// The mms-cpp template's Main.cpp, as it behaves: follow the left wall for ever.
#include "API.h"

int main(int argc, char* argv[]) {
    while (true) {
        if (!API::wallLeft()) {
            API::turnLeft();
        }
        while (API::wallFront()) {
            API::turnRight();
        }
        API::moveForward();
    }
}
