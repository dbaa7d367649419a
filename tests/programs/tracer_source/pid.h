/* The tracer's gains, as constants no other kind can reach. */
static const float KP_GAIN = 1.0f;
static const float KI_GAIN = 0.5f;
static const float KD_GAIN = 0.5f;
static const float BASE_POWER = 15.0f;
