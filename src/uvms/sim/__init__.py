"""Time-domain simulation: the state vector, compiled RK4 and adaptive integration, scenarios and results."""
