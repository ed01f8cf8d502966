"""Problems: benchmark functions and the toolpath engine, as batched pymoo problems."""
