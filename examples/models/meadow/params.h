/* The meadow flower's proportions (plant.l includes this file, as cpfg models do). */
#define STEPS 9     /* derivation steps */
#define FORK 4      /* internodes of the main stem before it forks */
#define LEN 1.0     /* internode length */
#define SHRINK 0.8  /* each fork's internodes, relative to the one below */
#define FLOWER 0.3  /* flower diameter */
