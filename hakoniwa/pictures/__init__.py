"""The physics' pictures, made after a test or beside it: the scene (a second MuJoCo model that is only drawn),
films of a recorded test, the live viewer and the course plots. They read the physics and never step it, so
the physics process loads none of them unless a person asks to look."""
