"""Problems: benchmark functions and the toolpath simulator, as batched pymoo problems."""
